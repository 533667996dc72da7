#include "free_rays.h"

#include <algorithm>
#include <optional>
#include <stdexcept>

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

// A message of counts: per block, its coordinates, the number n of its cells counted, then n
// pairs (offset in the block, count). Blocks with no count go too: the walk that entered
// them made them part of the scan, as in the serial walk.
constexpr size_t kBlockHeaderWords = 4;

void appendBlock(const CellIndex& b, const CountBlock& counts, std::vector<uint32_t>& words) {
  const size_t header = words.size();
  words.insert(words.end(), {uint32_t(b.x), uint32_t(b.y), uint32_t(b.z), 0});
  uint32_t n = 0;
  for (uint32_t i = 0; i < uint32_t(kBlockCells); ++i) {
    if (counts.count[i] == 0) continue;
    words.push_back(i);
    words.push_back(counts.count[i]);
    ++n;
  }
  words[header + 3] = n;
}

void addMessage(const std::vector<uint32_t>& words, const TileOwnership& owned, ScanCounts& into) {
  auto malformed = [] {
    return std::runtime_error("insertScanPart: a malformed message of counts from another process");
  };
  for (size_t at = 0; at < words.size();) {
    if (words.size() - at < kBlockHeaderWords) throw malformed();
    const CellIndex b{int32_t(words[at]), int32_t(words[at + 1]), int32_t(words[at + 2])};
    const size_t n = words[at + 3];
    at += kBlockHeaderWords;
    if (!owned.ownsBlock(b) || n > size_t(kBlockCells) || (words.size() - at) / 2 < n)
      throw malformed();
    CountBlock& block = into.blockAt(b);
    for (size_t k = 0; k < n; ++k, at += 2) {
      if (words[at] >= uint32_t(kBlockCells)) throw malformed();
      block.count[words[at]] += words[at + 1];
    }
  }
}

// Sends the counts in other processes' tiles to their owners and adds theirs in this one's
// tiles as one more table (the apply stage sums the tables).
void tradeCounts(const TileOwnership& owned, CountExchange& exchange, size_t threads,
                 FreeCounts& out) {
  out.outgoing.resize(size_t(owned.ranks));
  for (std::vector<uint32_t>& words : out.outgoing) words.clear();
  for (size_t t = 0; t < threads; ++t) {
    ScanCounts& table = out.tables[t];
    for (size_t i = 0; i < table.numBlocks(); ++i) {
      const CellIndex& b = table.blockIndex(i);
      const int owner = owned.ownerOfTile(tileOfBlock(b, owned.tile_blocks));
      if (owner != owned.rank) appendBlock(b, table.block(i), out.outgoing[size_t(owner)]);
    }
  }
  out.exchanged = true;
  if (!exchange.exchange(false, out.outgoing, out.incoming))
    throw std::runtime_error(
        "insertScanPart: another process of the distributed build failed on this scan");
  if (out.tables.size() < threads + 1) out.tables.resize(threads + 1);
  ScanCounts& received = out.tables[threads];
  received.setBlockLimit(nullptr);
  for (const std::vector<uint32_t>& words : out.incoming) addMessage(words, owned, received);
  out.used = threads + 1;
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
  // A process sharing the rays out walks a range of them, of its share of their length.
  const bool share_rays = scan.owned && scan.exchange;
  const size_t ranks = share_rays ? size_t(scan.owned->ranks) : 1;
  const size_t rank = share_rays ? size_t(scan.owned->rank) : 0;
  std::vector<size_t> bounds(threads + 1, items);
  bounds[0] = 0;
  if (threads > 1 || ranks > 1) {
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
    auto itemAt = [&](double fraction) {  // where that fraction of the total length is reached
      size_t piece = 0;
      while (piece < kPieces && cost[piece] < cost[kPieces] * fraction) ++piece;
      return partRange(items, kPieces, piece).first;
    };
    const double share = 1.0 / double(ranks);
    bounds[0] = rank == 0 ? 0 : itemAt(double(rank) * share);
    bounds[threads] = rank + 1 == ranks ? items : itemAt(double(rank + 1) * share);
    for (size_t t = 1; t < threads; ++t)
      bounds[t] = std::clamp(itemAt((double(rank) + double(t) / double(threads)) * share),
                             bounds[0], bounds[threads]);
  }
  // The owners of the tiles the rays cross: the box of their ends and the sensor.
  std::optional<OwnedTiles> tiles;
  if (scan.owned && !share_rays) {
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
        count = tiles ? walkOwnedRays(scan, *tiles, begin, end, endOf, count)
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
  // The stretches' walks also count a cell or two of other processes' tiles at their ends;
  // whole rays count in every tile, and those counts go to the tiles' owners.
  if (share_rays) tradeCounts(*scan.owned, *scan.exchange, threads, out);
  if (scan.owned)
    for (size_t t = 0; t < threads; ++t)
      out.tables[t].keepBlocksWhere([&](const CellIndex& b) { return scan.owned->ownsBlock(b); });
  report.rays_cast = rays;
  for (size_t n : visits) report.voxel_visits += n;
}

}  // namespace ndtom
