#include "scan_update.h"

#include <algorithm>
#include <stdexcept>

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
  if (s_.counts.empty()) s_.counts.resize(1);  // counts[0] is the union even without tracing
  s_.counts_used = 1;

  // Nothing below touches the map until applyToMap(), which cannot fail half-way.
  try {
    classifyPoints(points);
    groupEndsByCell();
    if (map_.options().occupancy.enabled) traceFreeRays();
    applyToMap();
  } catch (...) {
    for (ScanCounts& c : s_.counts) c.clear();  // the next scan starts from zero counters
    throw;
  }
  return report_;
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
  struct Part {
    InsertionReport report;
    CellIndex lo{kMaxCellIndex, kMaxCellIndex, kMaxCellIndex};
    CellIndex hi{-kMaxCellIndex, -kMaxCellIndex, -kMaxCellIndex};
  };
  const size_t threads = threadsFor(n, kMinPointsPerThread);
  std::vector<Part> parts(threads);
  runParallel(threads, [&](size_t t) {
    Part& part = parts[t];
    const auto [begin, end] = partRange(n, threads, t);
    for (size_t i = begin; i < end; ++i) {
      s_.kinds[i] = classifyPoint(points[i], s_.ends[i], part.report);
      if (s_.kinds[i] == PointKind::kRejected) continue;
      s_.end_cells[i] = map_.geometry().cellOf(s_.ends[i]);
      widen(part.lo, part.hi, s_.end_cells[i]);
    }
  });
  ends_lo_ = parts[0].lo;
  ends_hi_ = parts[0].hi;
  classify_threads_ = threads;
  s_.part_offsets.assign(1, 0);
  for (const Part& part : parts) {
    s_.part_offsets.push_back(s_.part_offsets.back() + part.report.pointsUsed());
    report_ += part.report;
    widen(ends_lo_, ends_hi_, part.lo);
    widen(ends_lo_, ends_hi_, part.hi);
  }
}

// Step 2: gather the ray ends per cell; a hit group's points give N_p and the batch that
// RCU merges into the cell (Eq. 2, 11).
void ScanUpdater::groupEndsByCell() {
  s_.groups.clear();
  s_.ray_ends.clear();
  group_means_ready_ = false;
  const size_t used = report_.pointsUsed();
  if (used == 0) return;
  // Block-major dense index within the ends' bounding box, so each block's groups are
  // contiguous (threads can own whole blocks); under 2^14 blocks per axis, because rays are
  // at most kMaxRayCells long.
  const CellIndex lo = blockOf(ends_lo_), hi = blockOf(ends_hi_);
  const uint64_t nx = uint64_t(hi.x - lo.x) + 1, ny = uint64_t(hi.y - lo.y) + 1;
  const uint64_t nz = uint64_t(hi.z - lo.z) + 1;
  s_.ray_ends.resize(used);
  runParallel(classify_threads_, [&](size_t t) {  // the chunks of classifyPoints
    const auto [begin, end] = partRange(s_.kinds.size(), classify_threads_, t);
    size_t k = s_.part_offsets[t];
    for (size_t i = begin; i < end; ++i) {
      if (s_.kinds[i] == PointKind::kRejected) continue;
      const CellIndex& c = s_.end_cells[i];
      const CellIndex b = blockOf(c);
      const uint64_t block =
          (uint64_t(b.z - lo.z) * ny + uint64_t(b.y - lo.y)) * nx + uint64_t(b.x - lo.x);
      const uint64_t dense = block * kBlockCells + uint64_t(offsetInBlock(c));
      s_.ray_ends[k++] = {dense << 1 | (s_.kinds[i] == PointKind::kHit ? 1u : 0u), uint32_t(i)};
    }
  });
  int key_bits = 1;
  while (key_bits < 64 && (uint64_t(1) << key_bits) < 2 * kBlockCells * nx * ny * nz) ++key_bits;
  radixSortByKey(s_.ray_ends, s_.sort_buffer, key_bits);
  // One gather with independent loads, instead of a dependent walk per group later.
  s_.sorted_ends.resize(used);
  const size_t gather_threads = threadsFor(used, kMinPointsPerThread);
  runParallel(gather_threads, [&](size_t t) {
    const auto [begin, end] = partRange(used, gather_threads, t);
    for (size_t i = begin; i < end; ++i) s_.sorted_ends[i] = s_.ends[s_.ray_ends[i].point];
  });

  for (size_t i = 0; i < used; ++i) {
    if (i > 0 && s_.ray_ends[i].key == s_.ray_ends[i - 1].key) {
      ++s_.groups.back().count;
      continue;
    }
    const bool hit = (s_.ray_ends[i].key & 1) != 0;
    s_.groups.push_back({s_.end_cells[s_.ray_ends[i].point], uint32_t(i), 1, hit,
                         Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
    report_.cells_hit += hit;
  }
  group_means_ready_ = options_.ray_mode == RayMode::PerHitCell && map_.options().occupancy.enabled;
  if (!group_means_ready_) return;

  // One ray per group, to the mean of its ends.
  const size_t threads = threadsFor(s_.groups.size(), kMinGroupsPerThread);
  runParallel(threads, [&](size_t t) {
    const auto [first, last] = partRange(s_.groups.size(), threads, t);
    for (size_t group = first; group < last; ++group) {
      EndGroup& g = s_.groups[group];
      const Eigen::Vector3d centre = map_.geometry().cellCenter(g.cell);
      g.mean = Eigen::Vector3d::Zero();
      for (uint32_t i = g.begin; i < g.begin + g.count; ++i) g.mean += s_.sorted_ends[i] - centre;
      g.mean /= double(g.count);
      g.mean_end = centre + g.mean;
    }
  });
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
  for (uint32_t i = g.begin; i < end; ++i) {
    const Eigen::Vector3d d = s_.sorted_ends[i] - centre - stats.mean;
    stats.scatter += d * d.transpose();
  }
  return stats;
}

// Step 3: count N_e, the rays crossing each cell without ending in it. Rays are split in
// contiguous chunks (neighbouring rays share cells) over threads with their own counters.
void ScanUpdater::traceFreeRays() {
  const bool per_point = options_.ray_mode == RayMode::PerPoint;
  const size_t rays = per_point ? report_.pointsUsed() : s_.groups.size();
  const size_t threads = threadsFor(rays, kMinRaysPerThread);
  if (s_.counts.size() < threads) s_.counts.resize(threads);
  s_.counts_used = threads;

  const GridGeometry& geometry = map_.geometry();
  std::vector<size_t> visits(threads, 0);
  runParallel(threads, [&](size_t t) {
    CountingWalker count(s_.counts[t]);
    if (per_point) {
      const auto [begin, end] = partRange(s_.kinds.size(), threads, t);
      for (size_t i = begin; i < end; ++i)
        if (s_.kinds[i] != PointKind::kRejected)
          count = walkRay(geometry, origin_, s_.ends[i], count);
    } else {
      const auto [begin, end] = partRange(s_.groups.size(), threads, t);
      for (size_t i = begin; i < end; ++i) {
        count.setWeight(s_.groups[i].count);
        count = walkRay(geometry, origin_, s_.groups[i].mean_end, count);
      }
    }
    visits[t] = count.visits();
  });
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
    for (size_t i = 0; i < s_.groups.size(); ++i)  // a block's groups are contiguous
      if (s_.groups[i].hit &&
          (i == 0 || blockOf(s_.groups[i].cell) != blockOf(s_.groups[i - 1].cell)))
        merged.blockAt(blockOf(s_.groups[i].cell));
    const size_t blocks = merged.numBlocks();
    s_.other_counts.resize(blocks * (tables - 1));
    for (size_t i = 0; i < blocks; ++i)
      for (size_t t = 1; t < tables; ++t)
        s_.other_counts[i * (tables - 1) + t - 1] = s_.counts[t].findBlock(merged.blockIndex(i));
    s_.map_blocks.resize(blocks);
    s_.created_blocks.reserve(blocks);
    for (size_t i = 0; i < blocks; ++i) {
      bool created = false;
      s_.map_blocks[i] = &grid.getOrCreate(merged.blockIndex(i), &created);
      if (created) s_.created_blocks.push_back(merged.blockIndex(i));
    }
    // Exact room for the hit cells without statistics: memory follows the statistics.
    const size_t groups = s_.groups.size();
    for (size_t first = 0, last = 0; first < groups; first = last) {
      const CellIndex b = blockOf(s_.groups[first].cell);
      NdtMap::Block* block = nullptr;
      size_t missing = 0;
      for (last = first; last < groups && blockOf(s_.groups[last].cell) == b; ++last) {
        const EndGroup& g = s_.groups[last];
        if (!g.hit) continue;
        if (!block) block = s_.map_blocks[size_t(merged.indexOf(b))];
        missing += !block->hasStats(offsetInBlock(g.cell));
      }
      if (missing > 0) block->stats.reserve(block->stats.size() + missing);
    }

    // Hit groups split in near-equal ranges that never share a block.
    hit_threads_ = threadsFor(report_.cells_hit, kMinGroupsPerThread);
    s_.hit_part_starts.assign(hit_threads_ + 1, groups);
    for (size_t t = 0; t < hit_threads_; ++t) {
      size_t start = partRange(groups, hit_threads_, t).first;
      while (start > 0 && start < groups &&
             blockOf(s_.groups[start].cell) == blockOf(s_.groups[start - 1].cell))
        ++start;
      s_.hit_part_starts[t] = std::max(start, t > 0 ? s_.hit_part_starts[t - 1] : 0);
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
  // A cell with hits in this scan takes the hit update only (Eq. 12, N_p > 0).
  runParallel(tables, [&](size_t t) {
    for (const EndGroup& g : s_.groups)
      if (g.hit)
        if (uint32_t* n = s_.counts[t].find(g.cell)) *n = 0;
  });
  allocateForApply();

  auto collect = [&](size_t threads) {
    for (size_t t = 0; t < threads; ++t) {
      ScanScratch::ApplyPart& part = s_.apply_parts[t];
      report_.cells_touched += part.touched;
      report_.cells_created += part.created;
      report_.gaussians_gained += part.gaussians_gained;
      report_.gaussians_lost += part.gaussians_lost;
      map_.num_cells_ += part.created;
      part.touched = part.created = part.gaussians_gained = part.gaussians_lost = 0;
    }
  };
  const size_t blocks = s_.counts[0].numBlocks();
  runParallel(apply_threads_, [&](size_t t) {
    const auto [begin, end] = partRange(blocks, apply_threads_, t);
    applyFreeCounts(begin, end, s_.apply_parts[t]);
  });
  collect(apply_threads_);
  runParallel(hit_threads_, [&](size_t t) {
    applyHits(s_.hit_part_starts[t], s_.hit_part_starts[t + 1], s_.apply_parts[t]);
  });
  collect(hit_threads_);
  runParallel(tables, [&](size_t t) { s_.counts[t].reset(); });  // their blocks are zero again
}

// Eq. 12 for the cells that rays crossed without a hit, in counts[0]'s blocks [begin, end):
// the bulk of the update.
void ScanUpdater::applyFreeCounts(size_t begin, size_t end, ScanScratch::ApplyPart& part) {
  const double lo = map_.options().occupancy.logodds_min;
  const double hi = map_.options().occupancy.logodds_max;
  const double miss = map_.options().occupancy.missLogOdds();
  const size_t others = s_.counts_used - 1;
  ScanCounts& merged = s_.counts[0];
  for (size_t b = begin; b < end; ++b) {
    CountBlock& counts = merged.block(b);
    for (size_t t = 0; t < others; ++t) {
      CountBlock* other = s_.other_counts[b * others + t];
      if (!other) continue;
      for (int k = 0; k < kBlockCells; ++k) counts.count[k] += other->count[k];
      other->zero();
    }
    NdtMap::Block& block = *s_.map_blocks[b];
    NdtMap::Block::Mask drop{};
    bool dropped = false;
    for (int g = 0; g < kBlockCells; g += kCountGroup) {
      uint32_t any = 0;  // tracking touched groups in the DDA would cost more than this test
      for (int k = 0; k < kCountGroup; ++k) any |= counts.count[g + k];
      if (any == 0) continue;
      for (int i = g; i < g + kCountGroup; ++i) {
        const uint32_t n = counts.count[i];
        if (n == 0) continue;
        ++part.touched;
        if (block.hasStats(i)) {
          const float logodds = map_.clampLogOdds(double(block.logodds[i]) + double(n) * miss);
          block.logodds[i] = logodds;
          if (logodds <= 0.f) {  // observed empty: the Gaussian goes
            part.gaussians_lost += block.stats[block.statsPos(i)].hasGaussian();
            drop[i >> 6] |= uint64_t(1) << (i & 63);
            dropped = true;
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
    if (dropped) block.eraseStats(drop);
    counts.zero();  // while it is in cache
  }
}

// Eq. 12 with N_p > 0 and the RCU merge (Eq. 2, 11) for the hit groups [first, last).
void ScanUpdater::applyHits(size_t first, size_t last, ScanScratch::ApplyPart& part) {
  const ScanCounts& merged = s_.counts[0];
  for (size_t begin = first, end = first; begin < last; begin = end) {
    const CellIndex b = blockOf(s_.groups[begin].cell);
    while (end < last && blockOf(s_.groups[end].cell) == b) ++end;
    if (const int64_t k = merged.indexOf(b); k >= 0)  // else only truncated ends: no hits
      applyHitsToBlock(*s_.map_blocks[size_t(k)], begin, end, part);
  }
}

// The same for one block's groups [first, last), in offset order. Statistics are merged in
// place; cells losing theirs are erased, then new ones inserted, each in one pass.
void ScanUpdater::applyHitsToBlock(NdtMap::Block& block, size_t first, size_t last,
                                   ScanScratch::ApplyPart& part) {
  const double hit = map_.options().occupancy.hitLogOdds();
  const bool occupancy = map_.options().occupancy.enabled;
  NdtMap::Block::Mask added{}, drop{};
  bool any_added = false, any_dropped = false;
  int word = 0;       // statistics positions advance with the offsets:
  size_t before = 0;  // cells with statistics in the words before `word`
  for (size_t group = first; group < last; ++group) {
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
    const int w = i >> 6;
    const uint64_t bit = uint64_t(1) << (i & 63);
    if (!(block.has_stats[w] & bit)) {
      added[w] |= empty ? 0 : bit;
      any_added |= !empty;
      continue;
    }
    for (; word < w; ++word) before += size_t(__builtin_popcountll(block.has_stats[word]));
    CellStats& stats =
        block.stats[before + size_t(__builtin_popcountll(block.has_stats[w] & (bit - 1)))];
    if (empty) {
      part.gaussians_lost += stats.hasGaussian();
      drop[w] |= bit;
      any_dropped = true;
      continue;
    }
    const bool had_gaussian = stats.hasGaussian();
    stats.merge(groupStats(g));
    part.gaussians_gained += !had_gaussian && stats.hasGaussian();
  }
  if (any_dropped) block.eraseStats(drop);
  if (any_added) insertNewStats(block, added, last, part);
}

// Gives the cells in `added` (hit by the block's groups before `last`) their statistics in one
// pass from the block's end down, moving each older entry once, within allocateForApply's room.
void ScanUpdater::insertNewStats(NdtMap::Block& block, const NdtMap::Block::Mask& added,
                                 size_t last, ScanScratch::ApplyPart& part) {
  size_t count = 0;
  for (const uint64_t bits : added) count += size_t(__builtin_popcountll(bits));
  size_t src = block.stats.size(), dst = src + count;
  block.stats.resize(dst);
  size_t group = last;
  for (int w = NdtMap::Block::kWords - 1; dst > src; --w) {
    uint64_t bits = block.has_stats[w] | added[w];
    while (bits != 0 && dst > src) {
      const int b = 63 - __builtin_clzll(bits);
      const uint64_t bit = uint64_t(1) << b;
      bits &= ~bit;
      if (!(added[w] & bit)) {
        block.stats[--dst] = std::move(block.stats[--src]);
        continue;
      }
      const int i = w * 64 + b;
      do --group;
      while (!s_.groups[group].hit || offsetInBlock(s_.groups[group].cell) != i);
      block.stats[--dst] = groupStats(s_.groups[group]);
      part.gaussians_gained += block.stats[dst].hasGaussian();
    }
    block.has_stats[w] |= added[w];
  }
}

}  // namespace ndtom
