#include "insertion/apply_to_map.h"

#include <algorithm>
#include <atomic>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace ndtom {

namespace {

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

class MapUpdate {
 public:
  MapUpdate(const ScanContext& scan, const MapOptions& map_options, const EndGroups& groups,
            FreeCounts& counts, BlockGrid<MapBlock>& grid, ApplyBuffers& b)
      : scan_(scan), map_options_(map_options), groups_(groups), counts_(counts), grid_(grid),
        b_(b) {}

  MapChange run(InsertionReport& report);

 private:
  void allocate(size_t hits, size_t cells_hit);
  // The phases of allocate():
  void mergeCountBlocks();
  void findMapBlocks();
  void createNewBlocks();
  void reserveHitStats();
  void splitWork(size_t hits, size_t cells_hit);
  void applyFreeCounts(size_t begin, size_t end, ApplyBuffers::Part& part,
                       std::vector<ApplyBuffers::EmptiedCell>& emptied);
  void applyHits(const HitBlock& hit_block, ApplyBuffers::HitTarget& target,
                 ApplyBuffers::Part& part);
  float clampLogOdds(double l) const { return ndtom::clampLogOdds(l, map_options_.occupancy); }
  /// The update must not fail half-way: out of memory here, the record is marked incomplete
  /// (whoever follows the map's changes then rebuilds) and the update goes on.
  void recordEmptied(std::vector<ApplyBuffers::EmptiedCell>& emptied,
                     const ApplyBuffers::EmptiedCell& cell) noexcept {
    try {
      emptied.push_back(cell);
    } catch (...) {
      b_.emptied_complete = false;
    }
  }

  const ScanContext& scan_;
  const MapOptions& map_options_;
  const EndGroups& groups_;
  FreeCounts& counts_;
  BlockGrid<MapBlock>& grid_;
  ApplyBuffers& b_;
  size_t free_threads_ = 1, hit_threads_ = 1;
  size_t traced_blocks_ = 0;  ///< tables[0]'s own blocks, [0, traced_blocks_): the rest are zero
};

MapChange MapUpdate::run(InsertionReport& report) {
  const size_t tables = counts_.used;
  // A cell with hits in this scan takes the hit update only (Eq. 12, N_p > 0): its free
  // counts are dropped, a table lookup per hit block.
  scan_.pool.run(tables, [&](size_t t) {
    for (const HitBlock& h : groups_.hit_blocks) {
      CountBlock* counts = counts_.tables[t].findBlock(blockOf(groups_.blockCell(h)));
      if (!counts) continue;
      for (int w = 0; w < MapBlock::kWords; ++w)
        for (uint64_t bits = h.hits[w]; bits != 0; bits &= bits - 1)
          counts->count[size_t(w * 64 + __builtin_ctzll(bits))] = 0;
    }
  });
  traced_blocks_ = counts_.tables[0].numBlocks();  // before the others merge in
  allocate(report.hits, report.cells_hit);

  MapChange change;
  auto collect = [&](size_t threads) {
    for (size_t t = 0; t < threads; ++t) {
      ApplyBuffers::Part& part = b_.parts[t];
      report.cells_touched += part.touched;
      report.cells_created += part.created;
      report.gaussians_gained += part.gaussians_gained;
      report.gaussians_lost += part.gaussians_lost;
      change.cells_created += part.created;
      change.stats_bytes += part.stats_bytes;
      part = ApplyBuffers::Part{};
    }
  };
  // Blocks differ in work, and each block's update stands alone: threads take small runs of
  // blocks as they go.
  const size_t blocks = counts_.tables[0].numBlocks();
  for (auto& cells : b_.emptied) cells.clear();
  b_.emptied_complete = true;
  constexpr size_t kBlocksPerTake = 16;
  std::atomic<size_t> next_block{0};
  scan_.pool.run(free_threads_, [&](size_t t) {
    for (;;) {
      const size_t begin = next_block.fetch_add(kBlocksPerTake, std::memory_order_relaxed);
      if (begin >= blocks) break;
      applyFreeCounts(begin, std::min(blocks, begin + kBlocksPerTake), b_.parts[t], b_.emptied[t]);
    }
  });
  collect(free_threads_);
  scan_.pool.run(hit_threads_, [&](size_t t) {
    for (size_t k = b_.hit_part_starts[t]; k < b_.hit_part_starts[t + 1]; ++k)
      applyHits(groups_.hit_blocks[k], b_.hit_targets[k], b_.parts[t]);
  });
  collect(hit_threads_);
  // Each table is zeroed by the thread that counts into it: its lines stay in that core's
  // cache for the next scan instead of moving to whichever core applied the block.
  scan_.pool.run(tables, [&](size_t t) {
    if (tables == 1)
      counts_.tables[t].reset();  // applyFreeCounts zeroed its blocks
    else if (t == 0)
      counts_.tables[t].clear(traced_blocks_);  // blocks merged in after the walk stayed zero
    else
      counts_.tables[t].clear();
  });
  return change;
}

// Everything the update needs from the allocator, so it cannot fail half-way: the union of
// the threads' counter blocks and the hit cells' blocks (in tables[0]), the map's blocks for
// them, and in each block room for the statistics its hit cells may gain.
void MapUpdate::allocate(size_t hits, size_t cells_hit) {
  b_.created_blocks.clear();
  try {
    mergeCountBlocks();
    findMapBlocks();
    createNewBlocks();
    reserveHitStats();
    splitWork(hits, cells_hit);
  } catch (...) {
    for (const CellIndex& b : b_.created_blocks) grid_.erase(b);
    throw;
  }
}

// tables[0] gets a block for every block of the other tables and of the hits.
void MapUpdate::mergeCountBlocks() {
  ScanCounts& merged = counts_.tables[0];
  for (size_t t = 1; t < counts_.used; ++t)
    for (size_t i = 0; i < counts_.tables[t].numBlocks(); ++i)
      merged.blockAt(counts_.tables[t].blockIndex(i));
  for (const HitBlock& h : groups_.hit_blocks) merged.blockAt(blockOf(groups_.blockCell(h)));
}

// For each block of tables[0], the other tables' counters and the map's block (null if new).
void MapUpdate::findMapBlocks() {
  const size_t tables = counts_.used;
  const ScanCounts& merged = counts_.tables[0];
  const size_t blocks = merged.numBlocks();
  b_.other_counts.resize(blocks * (tables - 1));
  b_.map_blocks.resize(blocks);
  // Lookups only (nothing is created until createNewBlocks), a hash lookup and likely a
  // cache miss each: split over threads.
  const size_t lookup_threads = scan_.threadsFor(blocks, kMinBlocksPerThread);
  scan_.pool.run(lookup_threads, [&](size_t t) {
    const auto [begin, end] = partRange(blocks, lookup_threads, t);
    for (size_t i = begin; i < end; ++i) {
      const CellIndex& b = merged.blockIndex(i);
      for (size_t k = 1; k < tables; ++k)
        b_.other_counts[i * (tables - 1) + k - 1] = counts_.tables[k].findBlock(b);
      b_.map_blocks[i] = grid_.find(b);
    }
  });
}

// New blocks are created in coordinate order, not in the order the tables met them: the
// map's iteration order (hence e.g. coarsened()) then does not depend on how the rays were
// shared among threads.
void MapUpdate::createNewBlocks() {
  const ScanCounts& merged = counts_.tables[0];
  b_.new_blocks.clear();
  for (size_t i = 0; i < merged.numBlocks(); ++i)
    if (!b_.map_blocks[i]) b_.new_blocks.push_back(i);
  std::sort(b_.new_blocks.begin(), b_.new_blocks.end(),
            [&](size_t a, size_t b) { return merged.blockIndex(a) < merged.blockIndex(b); });
  b_.created_blocks.reserve(b_.new_blocks.size());
  for (const size_t i : b_.new_blocks) {
    b_.map_blocks[i] = &grid_.getOrCreate(merged.blockIndex(i));
    b_.created_blocks.push_back(merged.blockIndex(i));
  }
}

// Exact room for the statistics each hit block's cells may gain (hit cells without any):
// memory follows the statistics. Each hit block on its own, split over threads.
void MapUpdate::reserveHitStats() {
  const ScanCounts& merged = counts_.tables[0];
  const std::vector<HitBlock>& hit_blocks = groups_.hit_blocks;
  b_.hit_targets.clear();  // no capacity left from a scan that failed here
  b_.hit_targets.resize(hit_blocks.size());
  const size_t reserve_threads = scan_.threadsFor(hit_blocks.size(), kMinBlocksPerThread);
  scan_.pool.run(reserve_threads, [&](size_t t) {
    const auto [begin, end] = partRange(hit_blocks.size(), reserve_threads, t);
    for (size_t k = begin; k < end; ++k) {
      const HitBlock& h = hit_blocks[k];
      ApplyBuffers::HitTarget& target = b_.hit_targets[k];
      target.block = b_.map_blocks[size_t(merged.indexOf(blockOf(groups_.blockCell(h))))];
      size_t missing = 0;
      for (int w = 0; w < MapBlock::kWords; ++w)
        if (const uint64_t m = h.hits[w] & ~target.block->has_stats[w])
          missing += size_t(__builtin_popcountll(m));
      if (missing > 0) target.grown.reserve(target.block->stats.size() + missing);
    }
  });
}

// Hit blocks split in ranges of near-equal numbers of ray ends: a hit cell's update reads all
// its points (coarse cells hold tens), and its merge comes on top.
void MapUpdate::splitWork(size_t hits, size_t cells_hit) {
  const std::vector<HitBlock>& hit_blocks = groups_.hit_blocks;
  hit_threads_ = std::max(scan_.threadsFor(hits, kMinPointsPerThread),
                          scan_.threadsFor(cells_hit, kMinGroupsPerThread));
  b_.hit_part_starts.resize(hit_threads_ + 1);
  for (size_t t = 0; t <= hit_threads_; ++t) {
    const size_t start = partRange(groups_.sorted_ends.size(), hit_threads_, t).first;
    b_.hit_part_starts[t] =
        size_t(std::lower_bound(hit_blocks.begin(), hit_blocks.end(), start,
                                [&](const HitBlock& h, size_t end) {
                                  return groups_.groups[h.first_group].begin < end;
                                }) -
               hit_blocks.begin());
  }
  free_threads_ = scan_.threadsFor(counts_.tables[0].numBlocks(), kMinBlocksPerThread);
  if (b_.emptied.size() < free_threads_) b_.emptied.resize(free_threads_);
  const size_t parts = std::max(free_threads_, hit_threads_);
  if (b_.parts.size() < parts) b_.parts.resize(parts);
}

// Eq. 12 for the cells that rays crossed without a hit, in tables[0]'s blocks [begin, end):
// the bulk of the update.
void MapUpdate::applyFreeCounts(size_t begin, size_t end, ApplyBuffers::Part& part,
                                std::vector<ApplyBuffers::EmptiedCell>& emptied) {
  const double lo = map_options_.occupancy.logodds_min;
  const double hi = map_options_.occupancy.logodds_max;
  const double miss = map_options_.occupancy.missLogOdds();
  const size_t others = counts_.used - 1;
  ScanCounts& merged = counts_.tables[0];
  alignas(64) std::array<uint32_t, kBlockCells> sum;
  for (size_t b = begin; b < end; ++b) {
    // With several tables the sum goes to a local buffer: the tables are only read here, so
    // their cache lines stay with the threads that count into them. A block walked by one
    // thread only (most: each walks a fan of neighbouring rays) is read where it is, and
    // tables[0]'s blocks merged in after the walk are zero: neither is read or copied.
    const uint32_t* count = b < traced_blocks_ ? merged.block(b).count.data() : nullptr;
    if (others > 0) {
      bool summed = false;
      for (size_t t = 0; t < others; ++t) {
        const CountBlock* other = b_.other_counts[b * others + t];
        if (!other) continue;
        if (!count) {
          count = other->count.data();
          continue;
        }
        if (!summed) {
          std::copy_n(count, kBlockCells, sum.data());
          summed = true;
        }
        for (int k = 0; k < kBlockCells; ++k) sum[size_t(k)] += other->count[size_t(k)];
      }
      if (summed) count = sum.data();
    }
    if (!count) continue;  // a hit block no ray crossed elsewhere: nothing free in it
    MapBlock& block = *b_.map_blocks[b];
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
          const float logodds = clampLogOdds(double(block.logodds[i]) + double(n) * miss);
          block.logodds[i] = logodds;
          if (logodds <= 0.f) {  // observed empty
            part.gaussians_lost += block.eraseStats(i);
            recordEmptied(emptied, {merged.blockIndex(b), i});
          }
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
// some, moved with the new ones into the array allocate() made.
void MapUpdate::applyHits(const HitBlock& hb, ApplyBuffers::HitTarget& target,
                          ApplyBuffers::Part& part) {
  const double hit = map_options_.occupancy.hitLogOdds();
  const bool occupancy = map_options_.occupancy.enabled;
  const GridGeometry& geometry = scan_.geometry;
  const double half_cell = 0.5 * geometry.resolution();
  MapBlock& block = *target.block;
  std::vector<CellStats>* grown = target.grown.capacity() > 0 ? &target.grown : nullptr;
  const MapBlock::Mask had = block.has_stats;
  size_t src = 0;          // position in block.stats of the next cell in `had`
  int word = 0;            // that cell is in had[word], among
  uint64_t bits = had[0];  // the bits not passed yet
  // Passes the cells with statistics before offset `end`, moving them if the block grows.
  auto passTo = [&](int end) {
    for (;;) {
      while (bits == 0 && word + 1 < MapBlock::kWords) bits = had[++word];
      if (bits == 0 || word * 64 + __builtin_ctzll(bits) >= end) return;
      if (grown) grown->push_back(std::move(block.stats[src]));
      ++src;
      bits &= bits - 1;
    }
  };
  for (size_t group = hb.first_group; group < hb.last_group; ++group) {
    const EndGroup& g = groups_.groups[group];
    if (!g.hit) continue;
    const int i = offsetInBlock(g.cell);
    ++part.touched;
    if (!block.known[i]) {
      block.known.set(i);
      block.logodds[i] = 0.f;
      ++part.created;
    }
    const float logodds = clampLogOdds(double(block.logodds[i]) + double(g.count) * hit);
    block.logodds[i] = logodds;
    // Still observed empty: no Gaussian; later hits start a new one.
    const bool empty = occupancy && logodds <= 0.f;
    const uint64_t bit = uint64_t(1) << (i & 63);
    passTo(i);
    if (!(had[i >> 6] & bit)) {
      if (empty) continue;
      grown->push_back(groupStats(groups_, g, geometry));  // allocate() counted this cell
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
    stats.merge(groupStats(groups_, g, geometry));
    stats.clampMean(half_cell);
    part.gaussians_gained += !had_gaussian && stats.hasGaussian();
    if (grown) grown->push_back(std::move(stats));
  }
  if (!grown) return;
  passTo(kBlockCells);
  part.stats_bytes += statsBytes(*grown) - statsBytes(block.stats);
  block.stats.swap(*grown);
  std::vector<CellStats>().swap(*grown);  // frees the old array
}

}  // namespace

MapChange applyToMap(const ScanContext& scan, const MapOptions& map_options,
                     const EndGroups& groups, FreeCounts& counts, BlockGrid<MapBlock>& grid,
                     ApplyBuffers& buffers, InsertionReport& report) {
  return MapUpdate(scan, map_options, groups, counts, grid, buffers).run(report);
}

}  // namespace ndtom
