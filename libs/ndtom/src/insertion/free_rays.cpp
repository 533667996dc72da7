#include "free_rays.h"

#include <algorithm>
#include <optional>

#include "ndtom/owned_ray_walk.h"
#include "ndtom/owned_tiles.h"
#include "ndtom/ray_dda.h"

namespace ndtom {

namespace {

// Rays [begin, end) through the owned tiles only. Not inlined, as walkSerialRays below.
template <class Walker, class RayEnd>
[[gnu::noinline]] Walker walkOwnedRays(const ScanContext& scan, const OwnedTiles& tiles,
                                       size_t begin, size_t end, RayEnd&& rayEnd, Walker count) {
  return OwnedRayWalk::walkRays(scan.geometry, scan.origin, begin, end, tiles, rayEnd, count);
}

// The serial walk of rays [begin, end), one function per walker and ray end: compiled on its
// own, the walk keeps its registers whatever else the caller holds.
template <class Walker, class RayEnd>
[[gnu::noinline]] Walker walkSerialRays(const ScanContext& scan, size_t begin, size_t end,
                                        RayEnd&& rayEnd, Walker count) {
  return walkRays(scan.geometry, scan.origin, begin, end, rayEnd, count);
}

}  // namespace

void traceFreeRays(const ScanContext& scan, const ClassifiedPoints& points,
                   const EndGroups& groups, std::atomic<int64_t>& blocks_left, FreeCounts& out,
                   InsertionReport& report) {
  constexpr size_t kPieces = ClassifiedPoints::kRayPieces;
  const bool per_point = scan.options.ray_mode == RayMode::PerPoint;
  const size_t rays = per_point ? points.used : groups.groups.size();
  const size_t threads = scan.threadsFor(rays, kMinRaysPerThread);
  if (out.tables.size() < threads) out.tables.resize(threads);
  out.used = threads;
  for (size_t t = 0; t < threads; ++t) out.tables[t].setBlockLimit(&blocks_left);
  struct Unlimit {  // the apply stage adds blocks already paid for
    FreeCounts& counts;
    ~Unlimit() {
      for (ScanCounts& c : counts.tables) c.setBlockLimit(nullptr);
    }
  } unlimit{out};

  const GridGeometry& geometry = scan.geometry;
  const Eigen::Vector3d origin = scan.origin;
  std::vector<size_t> visits(threads, 0);
  // Each thread walks a contiguous range of rays (neighbouring rays share cells, so its table
  // stays small), the ranges of near-equal total ray length (what a walk costs); a thread done
  // with its range helps with the others' (a ray's cost is only roughly its length).
  const size_t items = per_point ? points.points() : groups.groups.size();
  auto rayEnd = [&](size_t i) -> const Eigen::Vector3d* {
    if (!per_point) return &groups.groups[i].mean_end;
    return points.kinds[i] == PointKind::kRejected ? nullptr : &points.ends[i];
  };
  std::vector<size_t> bounds(threads + 1, items);
  bounds[0] = 0;
  if (threads > 1) {
    std::vector<double> cost(kPieces + 1, 0.0);  // [piece + 1]: lengths up to its end
    if (per_point) {
      std::copy(points.piece_lengths.begin(), points.piece_lengths.end(), cost.begin() + 1);
    } else {
      scan.pool.run(threads, [&](size_t t) {
        const auto [first, last] = partRange(kPieces, threads, t);
        for (size_t piece = first; piece < last; ++piece) {
          const auto [begin, end] = partRange(items, kPieces, piece);
          double sum = 0;
          for (size_t i = begin; i < end; ++i) sum += (*rayEnd(i) - origin).lpNorm<1>();
          cost[piece + 1] = sum;
        }
      });
    }
    for (size_t piece = 0; piece < kPieces; ++piece) cost[piece + 1] += cost[piece];
    for (size_t t = 1, piece = 0; t < threads; ++t) {
      while (piece < kPieces && cost[piece] < cost[kPieces] * double(t) / double(threads))
        ++piece;
      bounds[t] = partRange(items, kPieces, piece).first;
    }
  }
  // The owners of the tiles the rays cross: the box of their ends and the sensor.
  std::optional<OwnedTiles> tiles;
  if (scan.owned) {
    const CellIndex o = geometry.cellOf(origin);
    tiles.emplace(*scan.owned, cellwiseMin(points.ends_lo, o), cellwiseMax(points.ends_hi, o));
  }
  struct alignas(64) Cursor {  // the next ray of a range; own cache line
    std::atomic<size_t> next{0};
  };
  std::vector<Cursor> cursors(threads);
  for (size_t t = 0; t < threads; ++t) cursors[t].next.store(bounds[t], std::memory_order_relaxed);
  constexpr size_t kRaysPerTake = 256;
  scan.pool.run(threads, [&](size_t t) {
    auto forEachTake = [&](auto&& walkRange) {
      for (size_t k = 0; k < threads; ++k) {  // its own range first, then the others'
        const size_t range = (t + k) % threads, range_end = bounds[range + 1];
        for (;;) {
          const size_t begin =
              cursors[range].next.fetch_add(kRaysPerTake, std::memory_order_relaxed);
          if (begin >= range_end) break;
          walkRange(begin, std::min(range_end, begin + kRaysPerTake));
        }
      }
    };
    // One walker type and one call per mode keep the mode out of the per-ray loop; a
    // distributed build's process walks only its tiles' stretches of the rays.
    auto walkTakes = [&](auto count, auto&& endOf) {
      forEachTake([&](size_t begin, size_t end) {
        count = scan.owned ? walkOwnedRays(scan, *tiles, begin, end, endOf, count)
                           : walkSerialRays(scan, begin, end, endOf, count);
      });
      visits[t] = count.visits();
    };
    if (per_point)
      walkTakes(UnitCountingWalker(out.tables[t]),
                [&](size_t i, UnitCountingWalker&) { return rayEnd(i); });
    else
      walkTakes(CountingWalker(out.tables[t]), [&](size_t i, CountingWalker& walker) {
        walker.setWeight(groups.groups[i].count);  // one ray per hit group, its weight
        return &groups.groups[i].mean_end;
      });
  });
  // The stretches' walks also count a cell or two of other processes' tiles at their ends.
  if (scan.owned)
    for (size_t t = 0; t < threads; ++t)
      out.tables[t].keepBlocksWhere([&](const CellIndex& b) { return scan.owned->ownsBlock(b); });
  report.rays_cast = rays;
  for (size_t n : visits) report.voxel_visits += n;
}

}  // namespace ndtom
