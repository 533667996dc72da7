#include "registration/usable_points.h"

#include <cstdint>

#include "ndtom/map/cell_index.h"

namespace ndtom::registration {

std::vector<Eigen::Vector3d> usablePoints(const std::vector<Eigen::Vector3d>& scan,
                                          double min_range, double max_range, double cell_size,
                                          Threads threads) {
  const GridGeometry grid(cell_size);
  auto usable = [&](const Eigen::Vector3d& p) {
    if (!grid.inRange(p)) return false;  // also drops NaN and inf
    const double range = p.norm();
    return range >= min_range && range <= max_range && range < kMaxUsableRange;
  };
  // Each part keeps its usable points' indices; the parts are then copied out in order.
  constexpr size_t kMinPointsPerThread = 4096;
  const size_t n = scan.size();
  const size_t parts = threads.forItems(n, kMinPointsPerThread);
  std::vector<std::vector<uint32_t>> kept(parts);
  std::vector<size_t> offsets(parts + 1, 0);
  threads.pool.run(parts, [&](size_t t) {
    const auto [begin, end] = partRange(n, parts, t);
    kept[t].reserve(end - begin);
    for (size_t i = begin; i < end; ++i)
      if (usable(scan[i])) kept[t].push_back(uint32_t(i));
  });
  for (size_t t = 0; t < parts; ++t) offsets[t + 1] = offsets[t] + kept[t].size();
  std::vector<Eigen::Vector3d> out(offsets[parts]);
  threads.pool.run(parts, [&](size_t t) {
    for (size_t k = 0; k < kept[t].size(); ++k) out[offsets[t] + k] = scan[kept[t][k]];
  });
  return out;
}

std::vector<Eigen::Vector3d> usablePoints(const std::vector<Eigen::Vector3d>& scan,
                                          double min_range, double max_range, double cell_size) {
  WorkerPool pool;  // one thread: run() calls back directly, no thread is started
  return usablePoints(scan, min_range, max_range, cell_size, Threads{pool, 1});
}

}  // namespace ndtom::registration
