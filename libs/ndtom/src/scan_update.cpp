#include "scan_update.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <unordered_map>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "ndtom/input_file.h"
#include "ndtom/ray_dda.h"
#include "parallel.h"
#include "radix_sort.h"

namespace ndtom {

namespace {

// A stage runs on fewer threads when it has little work: starting one costs tens of µs.
constexpr size_t kMinPointsPerThread = 8192;
constexpr size_t kMinRaysPerThread = 256;
constexpr size_t kMinGroupsPerThread = 2048;
constexpr size_t kMinBlocksPerThread = 32;

/// Bit k set if count[k] != 0, for the kCountGroup counters at `count`.
inline uint32_t crossedCells(const uint32_t* count) {
  static_assert(kCountGroup == 8, "two SSE2 loads per group");
#if defined(__SSE2__)
  const __m128i zero = _mm_setzero_si128();
  const __m128i low = _mm_loadu_si128(reinterpret_cast<const __m128i*>(count));
  const __m128i high = _mm_loadu_si128(reinterpret_cast<const __m128i*>(count + 4));
  const int zero_low = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(low, zero)));
  const int zero_high = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(high, zero)));
  return ~uint32_t(zero_low | zero_high << 4) & 0xffu;
#else
  uint32_t crossed = 0;
  for (int k = 0; k < kCountGroup; ++k) crossed |= uint32_t(count[k] != 0) << k;
  return crossed;
#endif
}

/// Bits needed to write `max_value` (at least 1).
inline int bitsFor(uint64_t max_value) {
  int bits = 1;
  while (bits < 64 && (max_value >> bits) != 0) ++bits;
  return bits;
}

inline void widen(CellIndex& lo, CellIndex& hi, const CellIndex& c) {
  lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
  hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
}

}  // namespace

size_t ScanUpdater::threadsFor(size_t items, size_t min_items_per_thread) const {
  return std::clamp<size_t>(items / min_items_per_thread, 1, size_t(options_.threads));
}

InsertionReport ScanUpdater::run(const std::vector<Eigen::Vector3d>& points,
                                 const Eigen::Vector3d& origin) {
  validate(options_);
  if (!map_.geometry().inRange(origin))
    throw std::invalid_argument("insertScan: sensor origin is not finite or outside the grid");
  origin_ = origin;
  report_ = InsertionReport{};
  report_.points_in = points.size();
  if (points.size() > UINT32_MAX)
    throw std::invalid_argument("insertScan: more than 2^32 points in one scan; split it");
  if (s_.counts.empty()) s_.counts.resize(1);  // counts[0] is the union even without tracing
  s_.counts_used = 1;
  checkBudgetForPoints(points.size());

  // Nothing below touches the map until applyToMap(), which cannot fail half-way.
  try {
    classifyPoints(points);
    groupEndsByCell();
    checkBudgetForEnds();
    if (map_.options().occupancy.enabled) traceFreeRays();
    applyToMap();
  } catch (const MemoryBudgetError&) {
    for (ScanCounts& c : s_.counts) c.releaseMemory();  // may hold the budget's worth
    throw;
  } catch (...) {
    for (ScanCounts& c : s_.counts) c.clear();  // the next scan starts from zero counters
    throw;
  }
  return report_;
}

void ScanUpdater::checkBudgetForPoints(size_t points) {
  budget_used_ = map_.memoryBytes() + points * kBytesPerPoint;
  if (budget_used_ > options_.memory_budget)
    throw MemoryBudgetError("insertScan: a scan of " + std::to_string(points) +
                                " points (the map takes " + megabytes(map_.memoryBytes()) + ")",
                            budget_used_, options_.memory_budget);
}

void ScanUpdater::checkBudgetForEnds() {
  // The hit cells' blocks and statistics, counted by groupEndsByCell: no pass over the groups.
  end_blocks_ = s_.hit_blocks.size();
  budget_used_ += report_.cells_hit * sizeof(CellStats) + end_blocks_ * kBytesPerNewBlock;
  const uint64_t budget = options_.memory_budget;
  if (budget_used_ > budget) {
    char resolution[32];
    std::snprintf(resolution, sizeof(resolution), "%g", map_.options().resolution);
    throw MemoryBudgetError("insertScan: a scan whose hits lie in " + std::to_string(end_blocks_) +
                                " blocks of 8^3 cells (resolution " + resolution + " m)",
                            budget_used_, budget);
  }
  blocks_left_.store(int64_t((budget - budget_used_) / kBytesPerNewBlock),
                     std::memory_order_relaxed);
}

// Step 1: drop bad points (counted), truncate far ones at max_range.
PointKind ScanUpdater::classifyPoint(const Eigen::Vector3d& p, Eigen::Vector3d& end,
                                     InsertionReport& report) const {
  const GridGeometry& geometry = map_.geometry();
  if (!p.allFinite()) {
    ++report.rejected_non_finite;
    return PointKind::kRejected;
  }
  if (!geometry.inRange(p)) {
    ++report.rejected_out_of_grid;
    return PointKind::kRejected;
  }
  const double range = (p - origin_).norm();
  if (range == 0.0 || range < options_.min_range) {
    ++report.rejected_too_close;
    return PointKind::kRejected;
  }
  if (std::min(range, options_.max_range) > kMaxRayCells * geometry.resolution()) {
    ++report.rejected_too_far;
    return PointKind::kRejected;
  }
  // Both ends inside the supported range, so every cell between them is too.
  if (range <= options_.max_range) {
    end = p;
    ++report.hits;
    return PointKind::kHit;
  }
  end = origin_ + (p - origin_) * (options_.max_range / range);
  ++report.truncated;
  return PointKind::kTruncated;
}

void ScanUpdater::classifyPoints(const std::vector<Eigen::Vector3d>& points) {
  const size_t n = points.size();
  s_.kinds.resize(n);
  s_.ends.resize(n);
  s_.end_cells.resize(n);
  struct alignas(64) Part {  // own cache line: threads update theirs per point
    InsertionReport report;
    CellIndex lo{kMaxCellIndex, kMaxCellIndex, kMaxCellIndex};
    CellIndex hi{-kMaxCellIndex, -kMaxCellIndex, -kMaxCellIndex};
  };
  const size_t threads = threadsFor(n, kMinPointsPerThread);
  std::vector<Part> parts(threads);
  const GridGeometry& geometry = map_.geometry();
  const double inv_resolution = geometry.invResolution();
  const double min_range = options_.min_range, max_range = options_.max_range;
  const double far_limit = kMaxRayCells * geometry.resolution();
  classify_threads_ = threads;
  s_.pool.run(threads, [&](size_t t) {
    Part& part = parts[t];
    size_t hits = 0;
    CellIndex lo = part.lo, hi = part.hi;  // in registers, not stored per point
    const auto [first_piece, last_piece] = partRange(kRayPieces, threads, t);
    for (size_t piece = first_piece; piece < last_piece; ++piece) {
      const auto [begin, end] = partRange(n, kRayPieces, piece);
      double length = 0;
      for (size_t i = begin; i < end; ++i) {
        const Eigen::Vector3d& p = points[i];
        const Eigen::Vector3d scaled = p * inv_resolution;
        const Eigen::Vector3d ray = p - origin_;
        const double range = ray.norm();
        // Most points are plain hits: one test of all of classifyPoint's conditions, in
        // registers (|scaled| < limit is false for NaN and inf too).
        if (scaled.cwiseAbs().maxCoeff() < double(kMaxCellIndex - 1) && range > 0.0 &&
            range >= min_range && range <= max_range && range <= far_limit) {
          ++hits;
          s_.kinds[i] = PointKind::kHit;
          s_.ends[i] = p;
          s_.end_cells[i] = GridGeometry::floorCell(scaled);
          length += ray.lpNorm<1>();
        } else {
          s_.kinds[i] = classifyPoint(p, s_.ends[i], part.report);
          if (s_.kinds[i] == PointKind::kRejected) continue;
          s_.end_cells[i] = geometry.cellOf(s_.ends[i]);
          length += (s_.ends[i] - origin_).lpNorm<1>();
        }
        widen(lo, hi, s_.end_cells[i]);
      }
      piece_lengths_[piece] = length;
    }
    part.lo = lo, part.hi = hi;
    part.report.hits += hits;
  });
  ends_lo_ = parts[0].lo;
  ends_hi_ = parts[0].hi;
  s_.part_offsets.assign(1, 0);
  for (const Part& part : parts) {
    s_.part_offsets.push_back(s_.part_offsets.back() + part.report.pointsUsed());
    report_ += part.report;
    widen(ends_lo_, ends_hi_, part.lo);
    widen(ends_lo_, ends_hi_, part.hi);
  }
}

std::pair<size_t, size_t> ScanUpdater::classifyChunk(size_t t) const {
  const size_t n = s_.kinds.size();
  const auto [first_piece, last_piece] = partRange(kRayPieces, classify_threads_, t);
  return {partRange(n, kRayPieces, first_piece).first, partRange(n, kRayPieces, last_piece).first};
}

// Step 2: gather the ray ends per cell; a hit group's points give N_p and the batch that
// RCU merges into the cell (Eq. 2, 11).
void ScanUpdater::groupEndsByCell() {
  s_.groups.clear();
  s_.hit_blocks.clear();
  s_.ray_ends.clear();
  group_means_ready_ = false;
  const size_t used = report_.pointsUsed();
  if (used == 0) return;
  // Cells keyed by a block-major dense index within the ends' bounding box, so each block's
  // groups are contiguous (threads can own whole blocks); under 2^14 blocks per axis, because
  // rays are at most kMaxRayCells long. The key goes above the point's index in one word.
  point_bits_ = bitsFor(s_.kinds.size() - 1);
  point_mask_ = (uint64_t(1) << point_bits_) - 1;
  const CellIndex lo = blockOf(ends_lo_), hi = blockOf(ends_hi_);
  const uint64_t nx = uint64_t(hi.x - lo.x) + 1, ny = uint64_t(hi.y - lo.y) + 1;
  const uint64_t nz = uint64_t(hi.z - lo.z) + 1;
  int key_bits = bitsFor(2 * kBlockCells * nx * ny * nz - 1);
  s_.ray_ends.resize(used);
  if (key_bits + point_bits_ <= 64) {
    s_.pool.run(classify_threads_, [&](size_t t) {  // the chunks of classifyPoints
      const auto [begin, end] = classifyChunk(t);
      size_t k = s_.part_offsets[t];
      for (size_t i = begin; i < end; ++i) {
        if (s_.kinds[i] == PointKind::kRejected) continue;
        const CellIndex& c = s_.end_cells[i];
        const CellIndex b = blockOf(c);
        const uint64_t block =
            (uint64_t(b.z - lo.z) * ny + uint64_t(b.y - lo.y)) * nx + uint64_t(b.x - lo.x);
        s_.ray_ends[k++] = rayEndWord(block * kBlockCells + uint64_t(offsetInBlock(c)), i);
      }
    });
  } else {
    key_bits = keyEndsByBlockRank();
  }
  const size_t threads = threadsFor(used, kMinPointsPerThread);
  radixSortByBits(s_.ray_ends, s_.sort_buffer, point_bits_, key_bits, s_.pool, threads);
  // Groups are runs of equal keys. Threads split the sorted ends at run boundaries; each
  // gathers its ends (independent loads, instead of a dependent walk per group later) and
  // counts its runs, then fills its part of the group list.
  s_.sorted_ends.resize(used);
  std::vector<size_t> starts(threads + 1, used), runs(threads + 1, 0);
  starts[0] = 0;
  for (size_t t = 1; t < threads; ++t) {
    size_t start = std::max(partRange(used, threads, t).first, starts[t - 1]);
    while (start > 0 && start < used && keyOf(s_.ray_ends[start]) == keyOf(s_.ray_ends[start - 1]))
      ++start;
    starts[t] = start;
  }
  s_.pool.run(threads, [&](size_t t) {
    constexpr size_t kAhead = 16;  // the loads are random: start them early
    const size_t begin = starts[t], end = starts[t + 1];
    for (size_t i = begin; i < end; ++i) {
      if (i + kAhead < end) __builtin_prefetch(&s_.ends[pointOf(s_.ray_ends[i + kAhead])]);
      s_.sorted_ends[i] = s_.ends[pointOf(s_.ray_ends[i])];
    }
    size_t count = 0;
    for (size_t i = begin; i < end; ++i)
      count += i == begin || keyOf(s_.ray_ends[i]) != keyOf(s_.ray_ends[i - 1]);
    runs[t + 1] = count;
  });
  for (size_t t = 0; t < threads; ++t) runs[t + 1] += runs[t];
  s_.groups.resize(runs[threads]);
  group_means_ready_ = options_.ray_mode == RayMode::PerHitCell && map_.options().occupancy.enabled;
  s_.pool.run(threads, [&](size_t t) {
    const GridGeometry& geometry = map_.geometry();
    size_t group = runs[t];
    for (size_t i = starts[t]; i < starts[t + 1]; ++group) {
      EndGroup& g = s_.groups[group];
      const uint64_t key = keyOf(s_.ray_ends[i]);
      g.begin = uint32_t(i);
      while (i < starts[t + 1] && keyOf(s_.ray_ends[i]) == key) ++i;
      g.count = uint32_t(i - g.begin);
      g.hit = (key & 1) != 0;
      // The cell again from the sorted end (read in a row), not end_cells (a random access).
      g.cell = geometry.cellOf(s_.sorted_ends[g.begin]);
      g.mean = g.mean_end = Eigen::Vector3d::Zero();
      if (!group_means_ready_) continue;
      // One ray per group, to the mean of its ends.
      const Eigen::Vector3d centre = geometry.cellCenter(g.cell);
      for (uint32_t k = g.begin; k < g.begin + g.count; ++k) g.mean += s_.sorted_ends[k] - centre;
      g.mean /= double(g.count);
      g.mean_end = centre + g.mean;
    }
  });

  // Hit cells and their blocks, from the keys (dense index = block * kBlockCells + offset).
  uint64_t last_hit_block = 0;  // dense index of s_.hit_blocks.back()'s block
  for (size_t group = 0; group < s_.groups.size(); ++group) {
    if (!s_.groups[group].hit) continue;
    ++report_.cells_hit;
    const uint64_t dense = keyOf(s_.ray_ends[s_.groups[group].begin]) >> 1;
    const uint64_t block = dense / kBlockCells;
    if (s_.hit_blocks.empty() || block != last_hit_block) {
      s_.hit_blocks.push_back({group, 0, nullptr, {}, {}});
      last_hit_block = block;
    }
    ScanScratch::HitBlock& h = s_.hit_blocks.back();
    h.last_group = group + 1;
    const uint64_t offset = dense % kBlockCells;
    h.hits[offset / 64] |= uint64_t(1) << (offset % 64);
  }
}

// Keys for ends so far apart that a dense index in their box does not fit a word with the
// point index (thousands of km at fine resolution: glitches): blocks numbered in the order the
// points meet them instead, one thread. Returns the key bits.
int ScanUpdater::keyEndsByBlockRank() {
  std::unordered_map<CellIndex, uint64_t, CellIndexHash> rank_of_block;
  CellIndex last_block{};
  uint64_t last_rank = UINT64_MAX;  // consecutive points mostly share a block
  size_t k = 0;
  for (size_t i = 0; i < s_.kinds.size(); ++i) {
    if (s_.kinds[i] == PointKind::kRejected) continue;
    const CellIndex& c = s_.end_cells[i];
    const CellIndex b = blockOf(c);
    if (last_rank == UINT64_MAX || b != last_block) {
      last_rank = rank_of_block.try_emplace(b, rank_of_block.size()).first->second;
      last_block = b;
    }
    s_.ray_ends[k++] = rayEndWord(last_rank * kBlockCells + uint64_t(offsetInBlock(c)), i);
  }
  const int key_bits = bitsFor(2 * kBlockCells * rank_of_block.size() - 1);
  if (key_bits + point_bits_ > 64)  // over 2^27 points, spread over kilometres
    throw std::invalid_argument("insertScan: " + std::to_string(s_.kinds.size()) +
                                " points spread over " + std::to_string(rank_of_block.size()) +
                                " blocks are too many for one scan; split it");
  return key_bits;
}

// Two-pass statistics (Eq. 1) of a group's points, relative to its cell's centre.
CellStats ScanUpdater::groupStats(const EndGroup& g) const {
  const Eigen::Vector3d centre = map_.geometry().cellCenter(g.cell);
  const uint32_t end = g.begin + g.count;
  CellStats stats;
  stats.n = g.count;
  if (group_means_ready_) {
    stats.mean = g.mean;
  } else {
    for (uint32_t i = g.begin; i < end; ++i) stats.mean += s_.sorted_ends[i] - centre;
    stats.mean /= double(g.count);
  }
  // Upper triangle in scalars: Eigen's d·dᵀ here goes through the stack and stalls on store
  // forwarding. Same sums in the same order, so the same bits.
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  for (uint32_t i = g.begin; i < end; ++i) {
    const Eigen::Vector3d d = s_.sorted_ends[i] - centre - stats.mean;
    xx += d.x() * d.x(), xy += d.x() * d.y(), xz += d.x() * d.z();
    yy += d.y() * d.y(), yz += d.y() * d.z(), zz += d.z() * d.z();
  }
  stats.scatter << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  stats.clampMean(map_.halfCell());
  return stats;
}

// Step 3: count N_e, the rays crossing each cell without ending in it, each thread into its
// own counter table.
void ScanUpdater::traceFreeRays() {
  const bool per_point = options_.ray_mode == RayMode::PerPoint;
  const size_t rays = per_point ? report_.pointsUsed() : s_.groups.size();
  const size_t threads = threadsFor(rays, kMinRaysPerThread);
  if (s_.counts.size() < threads) s_.counts.resize(threads);
  s_.counts_used = threads;
  // The memory budget: the tables may add the blocks checkBudgetForEnds() left, together.
  for (size_t t = 0; t < threads; ++t) s_.counts[t].setBlockLimit(&blocks_left_);
  struct Unlimit {  // allocateForApply adds blocks already paid for
    ScanScratch& s;
    ~Unlimit() {
      for (ScanCounts& c : s.counts) c.setBlockLimit(nullptr);
    }
  } unlimit{s_};

  const GridGeometry& geometry = map_.geometry();
  std::vector<size_t> visits(threads, 0);
  // Each thread walks a contiguous range of rays (neighbouring rays share cells, so its table
  // stays small), the ranges of near-equal total ray length (what a walk costs); a thread done
  // with its range helps with the others' (a ray's cost is only roughly its length). Which
  // thread walks a ray changes nothing in the map (allocateForApply).
  const size_t items = per_point ? s_.kinds.size() : s_.groups.size();
  auto rayEnd = [&](size_t i) -> const Eigen::Vector3d* {
    if (!per_point) return &s_.groups[i].mean_end;
    return s_.kinds[i] == PointKind::kRejected ? nullptr : &s_.ends[i];
  };
  std::vector<size_t> bounds(threads + 1, items);
  bounds[0] = 0;
  if (threads > 1) {
    std::vector<double> cost(kRayPieces + 1, 0.0);  // [piece + 1]: lengths up to its end
    if (per_point) {
      std::copy(piece_lengths_.begin(), piece_lengths_.end(), cost.begin() + 1);
    } else {
      s_.pool.run(threads, [&](size_t t) {
        const auto [first, last] = partRange(kRayPieces, threads, t);
        for (size_t piece = first; piece < last; ++piece) {
          const auto [begin, end] = partRange(items, kRayPieces, piece);
          double sum = 0;
          for (size_t i = begin; i < end; ++i) sum += (*rayEnd(i) - origin_).lpNorm<1>();
          cost[piece + 1] = sum;
        }
      });
    }
    for (size_t piece = 0; piece < kRayPieces; ++piece) cost[piece + 1] += cost[piece];
    for (size_t t = 1, piece = 0; t < threads; ++t) {
      while (piece < kRayPieces && cost[piece] < cost[kRayPieces] * double(t) / double(threads))
        ++piece;
      bounds[t] = partRange(items, kRayPieces, piece).first;
    }
  }
  struct alignas(64) Cursor {  // the next ray of a range; own cache line
    std::atomic<size_t> next{0};
  };
  std::vector<Cursor> cursors(threads);
  for (size_t t = 0; t < threads; ++t) cursors[t].next.store(bounds[t], std::memory_order_relaxed);
  constexpr size_t kRaysPerTake = 256;
  auto walk = [&](size_t t) {
    CountingWalker count(s_.counts[t]);
    for (size_t k = 0; k < threads; ++k) {  // its own range first, then the others'
      const size_t range = (t + k) % threads, range_end = bounds[range + 1];
      for (;;) {
        const size_t begin = cursors[range].next.fetch_add(kRaysPerTake, std::memory_order_relaxed);
        if (begin >= range_end) break;
        const size_t end = std::min(range_end, begin + kRaysPerTake);
        // One call per mode keeps the mode test out of the per-ray loop (+0.3 % instructions
        // in one call with the test inside).
        if (per_point) {
          count = walkRays(
              geometry, origin_, begin, end, [&](size_t i, CountingWalker&) { return rayEnd(i); },
              count);
        } else {
          count = walkRays(
              geometry, origin_, begin, end,
              [&](size_t i, CountingWalker& walker) {
                walker.setWeight(s_.groups[i].count);  // one ray per hit group, its weight
                return &s_.groups[i].mean_end;
              },
              count);
        }
      }
    }
    visits[t] = count.visits();
  };
  try {
    s_.pool.run(threads, walk);
  } catch (const BlockLimitReached&) {
    char resolution[32];
    std::snprintf(resolution, sizeof(resolution), "%g", map_.options().resolution);
    size_t blocks = end_blocks_;
    for (size_t t = 0; t < threads; ++t) blocks += s_.counts[t].numBlocks();
    throw MemoryBudgetError(
        "insertScan: a scan whose rays cross more than " + std::to_string(blocks) +
            " blocks of 8^3 cells (resolution " + resolution + " m)",
        budget_used_ + (blocks - end_blocks_ + 1) * kBytesPerNewBlock, options_.memory_budget);
  }
  report_.rays_cast = rays;
  for (size_t n : visits) report_.voxel_visits += n;
}

// Everything step 4 needs from the allocator, so the update itself cannot fail half-way:
// the union of the threads' counter blocks and the hit cells' blocks (in counts[0]), the
// map's blocks for them, and in each block room for the statistics its hit cells may gain.
void ScanUpdater::allocateForApply() {
  auto& grid = map_.grid_;
  const size_t tables = s_.counts_used;
  ScanCounts& merged = s_.counts[0];
  s_.created_blocks.clear();
  try {
    for (size_t t = 1; t < tables; ++t)
      for (size_t i = 0; i < s_.counts[t].numBlocks(); ++i)
        merged.blockAt(s_.counts[t].blockIndex(i));
    for (const ScanScratch::HitBlock& h : s_.hit_blocks)
      merged.blockAt(blockOf(s_.groups[h.first_group].cell));
    const size_t blocks = merged.numBlocks();
    s_.other_counts.resize(blocks * (tables - 1));
    s_.map_blocks.resize(blocks);
    // Lookups only (nothing is created until below), a hash lookup and likely a cache miss
    // each: split over threads.
    const size_t lookup_threads = threadsFor(blocks, kMinBlocksPerThread);
    s_.pool.run(lookup_threads, [&](size_t t) {
      const auto [begin, end] = partRange(blocks, lookup_threads, t);
      for (size_t i = begin; i < end; ++i) {
        const CellIndex& b = merged.blockIndex(i);
        for (size_t k = 1; k < tables; ++k)
          s_.other_counts[i * (tables - 1) + k - 1] = s_.counts[k].findBlock(b);
        s_.map_blocks[i] = grid.find(b);
      }
    });
    s_.new_blocks.clear();
    for (size_t i = 0; i < blocks; ++i)
      if (!s_.map_blocks[i]) s_.new_blocks.push_back(i);
    // New blocks are created in coordinate order, not in the order the tables met them: the
    // map's iteration order (hence e.g. coarsened()) then does not depend on how the rays
    // were shared among threads.
    std::sort(s_.new_blocks.begin(), s_.new_blocks.end(),
              [&](size_t a, size_t b) { return merged.blockIndex(a) < merged.blockIndex(b); });
    s_.created_blocks.reserve(s_.new_blocks.size());
    for (const size_t i : s_.new_blocks) {
      s_.map_blocks[i] = &grid.getOrCreate(merged.blockIndex(i));
      s_.created_blocks.push_back(merged.blockIndex(i));
    }
    // Exact room for the statistics each hit block's cells may gain (hit cells without
    // any): memory follows the statistics. Each hit block on its own, split over threads.
    const size_t reserve_threads = threadsFor(s_.hit_blocks.size(), kMinBlocksPerThread);
    s_.pool.run(reserve_threads, [&](size_t t) {
      const auto [begin, end] = partRange(s_.hit_blocks.size(), reserve_threads, t);
      for (size_t k = begin; k < end; ++k) {
        ScanScratch::HitBlock& h = s_.hit_blocks[k];
        h.block = s_.map_blocks[size_t(merged.indexOf(blockOf(s_.groups[h.first_group].cell)))];
        size_t missing = 0;
        for (int w = 0; w < NdtMap::Block::kWords; ++w)
          if (const uint64_t m = h.hits[w] & ~h.block->has_stats[w])
            missing += size_t(__builtin_popcountll(m));
        if (missing > 0) h.grown.reserve(h.block->stats.size() + missing);
      }
    });

    // Hit blocks split in ranges of near-equal numbers of ray ends: a hit cell's update
    // reads all its points (coarse cells hold tens), and its merge comes on top.
    hit_threads_ = std::max(threadsFor(report_.hits, kMinPointsPerThread),
                            threadsFor(report_.cells_hit, kMinGroupsPerThread));
    s_.hit_part_starts.resize(hit_threads_ + 1);
    for (size_t t = 0; t <= hit_threads_; ++t) {
      const size_t start = partRange(s_.sorted_ends.size(), hit_threads_, t).first;
      s_.hit_part_starts[t] =
          size_t(std::lower_bound(s_.hit_blocks.begin(), s_.hit_blocks.end(), start,
                                  [&](const ScanScratch::HitBlock& h, size_t end) {
                                    return s_.groups[h.first_group].begin < end;
                                  }) -
                 s_.hit_blocks.begin());
    }
    apply_threads_ = threadsFor(blocks, kMinBlocksPerThread);
    const size_t parts = std::max(apply_threads_, hit_threads_);
    if (s_.apply_parts.size() < parts) s_.apply_parts.resize(parts);
  } catch (...) {
    for (const CellIndex& b : s_.created_blocks) grid.erase(b);
    throw;
  }
}

// Step 4: Eq. 12 once per touched cell, and the RCU merge of the hits. Blocks are split over
// threads, each block (with its statistics) owned by one.
void ScanUpdater::applyToMap() {
  const size_t tables = s_.counts_used;
  // A cell with hits in this scan takes the hit update only (Eq. 12, N_p > 0): its free
  // counts are dropped, a table lookup per hit block.
  s_.pool.run(tables, [&](size_t t) {
    for (const ScanScratch::HitBlock& h : s_.hit_blocks) {
      CountBlock* counts = s_.counts[t].findBlock(blockOf(s_.groups[h.first_group].cell));
      if (!counts) continue;
      for (int w = 0; w < NdtMap::Block::kWords; ++w)
        for (uint64_t bits = h.hits[w]; bits != 0; bits &= bits - 1)
          counts->count[size_t(w * 64 + __builtin_ctzll(bits))] = 0;
    }
  });
  const size_t traced_blocks = s_.counts[0].numBlocks();  // before the others merge into it
  allocateForApply();

  auto collect = [&](size_t threads) {
    for (size_t t = 0; t < threads; ++t) {
      ScanScratch::ApplyPart& part = s_.apply_parts[t];
      report_.cells_touched += part.touched;
      report_.cells_created += part.created;
      report_.gaussians_gained += part.gaussians_gained;
      report_.gaussians_lost += part.gaussians_lost;
      map_.num_cells_ += part.created;
      map_.stats_bytes_ += part.stats_bytes;
      part.touched = part.created = part.gaussians_gained = part.gaussians_lost = 0;
      part.stats_bytes = 0;
    }
  };
  // Blocks differ in work, and each block's update stands alone: threads take small runs of
  // blocks as they go.
  const size_t blocks = s_.counts[0].numBlocks();
  constexpr size_t kBlocksPerTake = 16;
  std::atomic<size_t> next_block{0};
  s_.pool.run(apply_threads_, [&](size_t t) {
    for (;;) {
      const size_t begin = next_block.fetch_add(kBlocksPerTake, std::memory_order_relaxed);
      if (begin >= blocks) break;
      applyFreeCounts(begin, std::min(blocks, begin + kBlocksPerTake), s_.apply_parts[t]);
    }
  });
  collect(apply_threads_);
  s_.pool.run(hit_threads_, [&](size_t t) {
    for (size_t k = s_.hit_part_starts[t]; k < s_.hit_part_starts[t + 1]; ++k)
      applyHits(s_.hit_blocks[k], s_.apply_parts[t]);
  });
  collect(hit_threads_);
  // Each table is zeroed by the thread that counts into it: its lines stay in that core's
  // cache for the next scan instead of moving to whichever core applied the block.
  s_.pool.run(tables, [&](size_t t) {
    if (tables == 1)
      s_.counts[t].reset();  // applyFreeCounts zeroed its blocks
    else if (t == 0)
      s_.counts[t].clear(traced_blocks);  // blocks merged in after the walk stayed zero
    else
      s_.counts[t].clear();
  });
}

// Eq. 12 for the cells that rays crossed without a hit, in counts[0]'s blocks [begin, end):
// the bulk of the update.
void ScanUpdater::applyFreeCounts(size_t begin, size_t end, ScanScratch::ApplyPart& part) {
  const double lo = map_.options().occupancy.logodds_min;
  const double hi = map_.options().occupancy.logodds_max;
  const double miss = map_.options().occupancy.missLogOdds();
  const size_t others = s_.counts_used - 1;
  ScanCounts& merged = s_.counts[0];
  alignas(64) std::array<uint32_t, kBlockCells> sum;
  for (size_t b = begin; b < end; ++b) {
    // With several tables the sum goes to a local buffer: the tables are only read here, so
    // their cache lines stay with the threads that count into them.
    const uint32_t* count = merged.block(b).count.data();
    if (others > 0) {
      std::copy_n(count, kBlockCells, sum.data());
      for (size_t t = 0; t < others; ++t)
        if (const CountBlock* other = s_.other_counts[b * others + t])
          for (int k = 0; k < kBlockCells; ++k) sum[size_t(k)] += other->count[size_t(k)];
      count = sum.data();
    }
    NdtMap::Block& block = *s_.map_blocks[b];
    for (int g = 0; g < kBlockCells; g += kCountGroup) {
      // Visit only the crossed cells (a test per cell would be a coin-flip branch); tracking
      // touched groups in the DDA would cost more than finding them here.
      uint32_t crossed = crossedCells(count + g);
      if (crossed == 0) continue;
      // The group's has_stats word, loaded once: testing it is as cheap as a per-cell slot.
      static_assert(64 % kCountGroup == 0, "a group's bits lie in one word");
      const uint64_t has = block.has_stats[g >> 6];
      for (; crossed != 0; crossed &= crossed - 1) {
        const int i = g + __builtin_ctz(crossed);
        const uint32_t n = count[i];
        ++part.touched;
        if ((has >> (i & 63)) & 1) {
          const float logodds = map_.clampLogOdds(double(block.logodds[i]) + double(n) * miss);
          block.logodds[i] = logodds;
          if (logodds <= 0.f) part.gaussians_lost += block.eraseStats(i);  // observed empty
          continue;
        }
        if (!block.known[i]) {
          block.known.set(i);
          block.logodds[i] = 0.f;
          ++part.created;
        }
        block.logodds[i] = float(std::clamp(double(block.logodds[i]) + double(n) * miss, lo, hi));
      }
    }
    if (others == 0) merged.zeroBlock(b);  // while it is in cache
  }
}

// Eq. 12 with N_p > 0 and the RCU merge (Eq. 2, 11) for one block's hit groups, in offset
// order. The block's statistics are walked in step: updated in place or, if the block gains
// some, moved with the new ones into the array allocateForApply made.
void ScanUpdater::applyHits(ScanScratch::HitBlock& hb, ScanScratch::ApplyPart& part) {
  const double hit = map_.options().occupancy.hitLogOdds();
  const bool occupancy = map_.options().occupancy.enabled;
  NdtMap::Block& block = *hb.block;
  std::vector<CellStats>* grown = hb.grown.capacity() > 0 ? &hb.grown : nullptr;
  const NdtMap::Block::Mask had = block.has_stats;
  size_t src = 0;          // position in block.stats of the next cell in `had`
  int word = 0;            // that cell is in had[word], among
  uint64_t bits = had[0];  // the bits not passed yet
  // Passes the cells with statistics before offset `end`, moving them if the block grows.
  auto passTo = [&](int end) {
    for (;;) {
      while (bits == 0 && word + 1 < NdtMap::Block::kWords) bits = had[++word];
      if (bits == 0 || word * 64 + __builtin_ctzll(bits) >= end) return;
      if (grown) grown->push_back(std::move(block.stats[src]));
      ++src;
      bits &= bits - 1;
    }
  };
  for (size_t group = hb.first_group; group < hb.last_group; ++group) {
    const EndGroup& g = s_.groups[group];
    if (!g.hit) continue;
    const int i = offsetInBlock(g.cell);
    ++part.touched;
    if (!block.known[i]) {
      block.known.set(i);
      block.logodds[i] = 0.f;
      ++part.created;
    }
    const float logodds = map_.clampLogOdds(double(block.logodds[i]) + double(g.count) * hit);
    block.logodds[i] = logodds;
    // Still observed empty: no Gaussian; later hits start a new one.
    const bool empty = occupancy && logodds <= 0.f;
    const uint64_t bit = uint64_t(1) << (i & 63);
    passTo(i);
    if (!(had[i >> 6] & bit)) {
      if (empty) continue;
      grown->push_back(groupStats(g));  // allocateForApply counted this cell
      block.has_stats[i >> 6] |= bit;
      part.gaussians_gained += grown->back().hasGaussian();
      continue;
    }
    bits &= bits - 1;  // passTo stopped at cell i
    if (empty) {       // only setCell leaves statistics in an empty cell
      if (grown) {
        part.gaussians_lost += block.stats[src++].hasGaussian();
        block.has_stats[i >> 6] &= ~bit;
      } else {
        part.gaussians_lost += block.eraseStats(i);  // the next ones move down to src
      }
      continue;
    }
    CellStats& stats = block.stats[src++];
    const bool had_gaussian = stats.hasGaussian();
    stats.merge(groupStats(g));
    stats.clampMean(map_.halfCell());
    part.gaussians_gained += !had_gaussian && stats.hasGaussian();
    if (grown) grown->push_back(std::move(stats));
  }
  if (!grown) return;
  passTo(kBlockCells);
  part.stats_bytes += NdtMap::statsBytes(*grown) - NdtMap::statsBytes(block.stats);
  block.stats.swap(*grown);
  std::vector<CellStats>().swap(*grown);  // frees the old array
}

}  // namespace ndtom
