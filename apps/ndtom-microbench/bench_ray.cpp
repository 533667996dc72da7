// ndtom::traverseRay alone: cost per visited voxel for 30 m rays in random directions.
#include <benchmark/benchmark.h>

#include <random>

#include "map/ray_dda.h"

namespace {

void BM_TraverseRay(benchmark::State& state) {
  const double resolution = state.range(0) / 100.0;  // the argument is in cm
  const ndtom::GridGeometry geometry(resolution);
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> offset(0.0, resolution);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> rays(1024);
  for (auto& [from, to] : rays) {
    from = Eigen::Vector3d(offset(rng), offset(rng), offset(rng));
    to = from + 30.0 * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
  }
  uint64_t visits = 0;
  for (auto _ : state) {
    for (const auto& [from, to] : rays)
      ndtom::traverseRay(geometry, from, to, [&](const ndtom::CellIndex& c) {
        benchmark::DoNotOptimize(c);
        ++visits;
        return true;
      });
  }
  state.SetItemsProcessed(int64_t(visits));  // items/s = voxel visits per second
  // Seconds per visit, printed with an SI prefix (e.g. "4.1n" = 4.1 ns).
  state.counters["time_per_visit"] =
      benchmark::Counter(double(visits), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_TraverseRay)->Arg(10)->Arg(20)->Arg(40)->Unit(benchmark::kMicrosecond);

}  // namespace
