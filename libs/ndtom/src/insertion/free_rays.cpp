#include "insertion/free_rays.h"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "map/ray_dda.h"
#include "partition/count_message.h"
#include "partition/owned_ray_walk.h"
#include "partition/tile_owner_table.h"

namespace ndtom {

namespace {

// Rays [begin, end) through the owned tiles only. Not inlined, as walkSerialRays below.
template <class Walker, class RayEnd>
[[gnu::noinline]] Walker walkOwnedRays(const ScanContext& scan, const TileOwnerTable& tiles,
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

// The rays of one scan: one per used point, or one per group of ends.
struct Rays {
  const ClassifiedPoints& points;
  const EndGroups& groups;
  bool per_point;

  size_t count() const { return per_point ? points.used : groups.groups.size(); }
  size_t items() const { return per_point ? points.points() : groups.groups.size(); }
  const Eigen::Vector3d* end(size_t i) const {
    if (!per_point) return &groups.groups[i].mean_end;
    return points.kinds[i] == PointKind::kRejected ? nullptr : &points.ends[i];
  }
};

// Summed ray length (L1, what a walk costs) up to the end of each of the scan's pieces of rays:
// [piece + 1], with [0] = 0.
std::vector<double> cumulativeRayLength(const ScanContext& scan, const Rays& rays, size_t threads) {
  constexpr size_t kPieces = ClassifiedPoints::kRayPieces;
  std::vector<double> cost(kPieces + 1, 0.0);
  if (rays.per_point) {
    std::copy(rays.points.piece_lengths.begin(), rays.points.piece_lengths.end(), cost.begin() + 1);
  } else {
    scan.pool.run(threads, [&](size_t t) {
      const auto [first, last] = partRange(kPieces, threads, t);
      for (size_t piece = first; piece < last; ++piece) {
        const auto [begin, end] = partRange(rays.items(), kPieces, piece);
        double sum = 0;
        for (size_t i = begin; i < end; ++i) sum += (*rays.end(i) - scan.origin).lpNorm<1>();
        cost[piece + 1] = sum;
      }
    });
  }
  for (size_t piece = 0; piece < kPieces; ++piece) cost[piece + 1] += cost[piece];
  return cost;
}

// Each thread walks a contiguous range of rays (neighbouring rays share cells, so its table
// stays small), the ranges of near-equal total ray length; a process sharing the rays out
// walks a range of them, of its share of their length. Returns threads + 1 bounds.
std::vector<size_t> rayRanges(const ScanContext& scan, const ScanPart* part, const Rays& rays,
                              size_t threads) {
  // Per-point rays are shared with the points: this process's are all its own.
  const bool share_rays = part && part->exchange && !rays.per_point;
  const size_t ranks = share_rays ? size_t(part->owned.ranks) : 1;
  const size_t rank = share_rays ? size_t(part->owned.rank) : 0;
  const size_t items = rays.items();
  std::vector<size_t> bounds(threads + 1, items);
  bounds[0] = 0;
  if (threads == 1 && ranks == 1) return bounds;
  constexpr size_t kPieces = ClassifiedPoints::kRayPieces;
  const std::vector<double> cost = cumulativeRayLength(scan, rays, threads);
  auto itemAt = [&](double fraction) {  // where that fraction of the total length is reached
    size_t piece = 0;
    while (piece < kPieces && cost[piece] < cost[kPieces] * fraction) ++piece;
    return partRange(items, kPieces, piece).first;
  };
  const double share = 1.0 / double(ranks);
  bounds[0] = rank == 0 ? 0 : itemAt(double(rank) * share);
  bounds[threads] = rank + 1 == ranks ? items : itemAt(double(rank + 1) * share);
  for (size_t t = 1; t < threads; ++t)
    bounds[t] = std::clamp(itemAt((double(rank) + double(t) / double(threads)) * share), bounds[0],
                           bounds[threads]);
  return bounds;
}

// A process walking only its tiles' stretches needs the owners of the tiles the rays cross:
// the box of their ends and the sensor.
std::optional<TileOwnerTable> ownerTableFor(const ScanContext& scan, const ScanPart* part,
                                            const ClassifiedPoints& points) {
  if (!part || part->exchange) return std::nullopt;
  const CellIndex o = scan.geometry.cellOf(scan.origin);
  return TileOwnerTable(part->owned, cellwiseMin(points.ends_lo, o),
                        cellwiseMax(points.ends_hi, o));
}

// Walks the rays on `threads` threads into out.tables[t]; a thread done with its own range
// helps with the others' (a ray's cost is only roughly its length). Returns the cells visited.
size_t walkOnThreads(const ScanContext& scan, const Rays& rays, const std::vector<size_t>& bounds,
                     const std::optional<TileOwnerTable>& tiles, size_t threads, FreeCounts& out) {
  struct alignas(64) Cursor {  // the next ray of a range; own cache line
    std::atomic<size_t> next{0};
  };
  std::vector<Cursor> cursors(threads);
  for (size_t t = 0; t < threads; ++t) cursors[t].next.store(bounds[t], std::memory_order_relaxed);
  constexpr size_t kRaysPerTake = 256;
  std::vector<size_t> visits(threads, 0);
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
    // One walker type and one call per mode keep the mode out of the per-ray loop.
    auto walkTakes = [&](auto count, auto&& endOf) {
      forEachTake([&](size_t begin, size_t end) {
        count = tiles ? walkOwnedRays(scan, *tiles, begin, end, endOf, count)
                      : walkSerialRays(scan, begin, end, endOf, count);
      });
      visits[t] = count.visits();
    };
    if (rays.per_point)
      walkTakes(UnitCountingWalker(out.tables[t]),
                [&](size_t i, UnitCountingWalker&) { return rays.end(i); });
    else
      walkTakes(CountingWalker(out.tables[t]), [&](size_t i, CountingWalker& walker) {
        walker.setWeight(rays.groups.groups[i].count);  // one ray per hit group, its weight
        return &rays.groups.groups[i].mean_end;
      });
  });
  size_t total = 0;
  for (size_t n : visits) total += n;
  return total;
}

// Per-point rays shared out: this process's hits go to the owners of their tiles.
void routeHits(const ClassifiedPoints& points, const TileOwnership& owned, FreeCounts& out) {
  for (auto* lists : {&out.hits_to, &out.hits_from}) {
    lists->resize(size_t(owned.ranks));
    for (std::vector<Eigen::Vector3d>& hits : *lists) hits.clear();
  }
  CellIndex last_tile{};
  int owner = -1;  // consecutive points mostly share a tile
  for (size_t i = 0; i < points.points(); ++i) {
    if (points.kinds[i] != PointKind::kHit) continue;
    const CellIndex tile = tileOfBlock(blockOf(points.end_cells[i]), owned.tile_blocks);
    if (owner < 0 || tile != last_tile) owner = owned.ownerOfTile(tile), last_tile = tile;
    (owner == owned.rank ? out.hits_from : out.hits_to)[size_t(owner)].push_back(points.ends[i]);
  }
}

// Sends the counts in other processes' tiles to their owners and adds theirs in this one's
// tiles as one more table (the apply stage sums the tables); with the points shared out, the
// hits and point counts too.
void tradeCounts(const ScanContext& scan, const ClassifiedPoints& points, bool share_points,
                 const TileOwnership& owned, CountExchange& exchange, size_t threads,
                 FreeCounts& out, InsertionReport& report) {
  const size_t ranks = size_t(owned.ranks), rank = size_t(owned.rank);
  if (share_points) routeHits(points, owned, out);
  out.outgoing.resize(ranks);
  for (size_t r = 0; r < ranks; ++r) {
    std::vector<uint32_t>& words = out.outgoing[r];
    words.clear();
    if (r == rank) continue;
    if (share_points)
      appendMessageHead(report, out.hits_to[r].data(), out.hits_to[r].size(), words);
    else
      appendMessageHead(InsertionReport{}, nullptr, 0, words);
  }
  for (size_t t = 0; t < threads; ++t) {
    ScanCounts& table = out.tables[t];
    for (size_t i = 0; i < table.numBlocks(); ++i) {
      const CellIndex& b = table.blockIndex(i);
      const int owner = owned.ownerOfTile(tileOfBlock(b, owned.tile_blocks));
      if (owner != owned.rank)
        appendCountBlock(b, table.block(i).count.data(), out.outgoing[size_t(owner)]);
    }
  }
  exchangeOrStop(exchange, out, out.outgoing, out.incoming);
  if (out.tables.size() < threads + 1) out.tables.resize(threads + 1);
  ScanCounts& received = out.tables[threads];
  received.setBlockLimit(nullptr);
  out.used = threads + 1;
  InsertionReport others;
  std::vector<Eigen::Vector3d> no_hits;
  for (size_t r = 0; r < ranks; ++r) {
    if (r == rank) continue;
    const std::vector<uint32_t>& words = out.incoming[r];
    const size_t at = readMessageHead(words, owned, scan.geometry, others,
                                      share_points ? out.hits_from[r] : no_hits);
    addCountMessage(words, at, owned,
                    [&](const CellIndex& b) { return received.blockAt(b).count.data(); });
  }
  // The processes' shares add up to the scan (without sharing, every process has all of it).
  const size_t others_points = others.pointsUsed() + others.rejected();
  const size_t own_points = share_points ? report.pointsUsed() + report.rejected() : 0;
  if (!no_hits.empty() ||
      others_points != (share_points ? report.points_in - own_points : 0))
    throw malformedMessage();
  report += others;
}

}  // namespace

void traceFreeRays(const ScanContext& scan, const ScanPart* part, const ClassifiedPoints& points,
                   const EndGroups& groups, std::atomic<int64_t>& blocks_left, FreeCounts& out,
                   InsertionReport& report) {
  const Rays rays{points, groups, scan.options.ray_mode == RayMode::PerPoint};
  const size_t threads = scan.threadsFor(rays.count(), kMinRaysPerThread);
  if (out.tables.size() < threads) out.tables.resize(threads);
  out.used = threads;
  for (size_t t = 0; t < threads; ++t) out.tables[t].setBlockLimit(&blocks_left);
  struct Unlimit {  // the apply stage adds blocks already paid for
    FreeCounts& counts;
    ~Unlimit() {
      for (ScanCounts& c : counts.tables) c.setBlockLimit(nullptr);
    }
  } unlimit{out};

  const std::vector<size_t> bounds = rayRanges(scan, part, rays, threads);
  const std::optional<TileOwnerTable> tiles = ownerTableFor(scan, part, points);
  report.voxel_visits += walkOnThreads(scan, rays, bounds, tiles, threads, out);
  report.rays_cast = rays.count();
  if (!part) return;
  // The stretches' walks also count a cell or two of other processes' tiles at their ends;
  // whole rays count in every tile, and those counts go to the tiles' owners.
  if (part->exchange)
    tradeCounts(scan, points, rays.per_point, part->owned, *part->exchange, threads, out, report);
  for (size_t t = 0; t < threads; ++t)
    out.tables[t].keepBlocksWhere([&](const CellIndex& b) { return part->owned.ownsBlock(b); });
}

void exchangeOrStop(CountExchange& exchange, FreeCounts& counts,
                    const std::vector<std::vector<uint32_t>>& outgoing,
                    std::vector<std::vector<uint32_t>>& incoming) {
  --counts.exchanges_left;
  if (!exchange.exchange(false, outgoing, incoming)) {
    counts.exchanges_left = 0;  // every process stops here
    throw std::runtime_error(
        "insertScanPart: another process of the distributed build failed on this scan");
  }
}

}  // namespace ndtom
