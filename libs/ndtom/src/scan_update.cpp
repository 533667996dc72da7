#include "scan_update.h"

#include <algorithm>
#include <exception>
#include <stdexcept>
#include <thread>

#include "ndtom/ray_dda.h"
#include "radix_sort.h"

namespace ndtom {

InsertionReport ScanUpdater::run(const std::vector<Eigen::Vector3d>& points,
                                 const Eigen::Vector3d& origin) {
  validate(options_);
  if (!map_.geometry().inRange(origin))
    throw std::invalid_argument("insertScan: sensor origin is not finite or outside the grid");
  origin_ = origin;
  report_ = InsertionReport{};
  report_.points_in = points.size();

  // Nothing below touches the map until applyToMap(), which cannot fail half-way.
  classifyPoints(points);
  groupEndsByCell();
  if (map_.options().occupancy.enabled) traceFreeRays();
  applyToMap();
  return report_;
}

// Step 1: drop bad points (counted), truncate far ones at max_range.
void ScanUpdater::classifyPoints(const std::vector<Eigen::Vector3d>& points) {
  const GridGeometry& geometry = map_.geometry();
  const double max_ray_length = kMaxRayCells * geometry.resolution();
  s_.ends.clear();
  s_.end_cells.clear();
  s_.ray_ends.clear();
  s_.ends.reserve(points.size());
  s_.end_cells.reserve(points.size());
  s_.ray_ends.reserve(points.size());
  for (const Eigen::Vector3d& p : points) {
    if (!p.allFinite()) {
      ++report_.rejected_non_finite;
      continue;
    }
    if (!geometry.inRange(p)) {
      ++report_.rejected_out_of_grid;
      continue;
    }
    const double range = (p - origin_).norm();
    if (range == 0.0 || range < options_.min_range) {
      ++report_.rejected_too_close;
      continue;
    }
    if (std::min(range, options_.max_range) > max_ray_length) {
      ++report_.rejected_too_far;
      continue;
    }
    // Both ends inside the supported range, so every cell between them is too.
    const bool hit = range <= options_.max_range;
    const Eigen::Vector3d end =
        hit ? p : Eigen::Vector3d(origin_ + (p - origin_) * (options_.max_range / range));
    s_.ray_ends.push_back({hit ? 1u : 0u, uint32_t(s_.ends.size())});
    s_.ends.push_back(end);
    s_.end_cells.push_back(geometry.cellOf(end));
    ++(hit ? report_.hits : report_.truncated);
  }
}

// Step 2: gather the ray ends per cell; a hit group's points give N_p and the batch that
// RCU merges into the cell (Eq. 2, 11).
void ScanUpdater::groupEndsByCell() {
  s_.groups.clear();
  if (s_.ray_ends.empty()) return;
  // Dense cell index within the ends' bounding box: at most 2^18 cells per axis, because
  // rays are at most kMaxRayCells long.
  CellIndex lo = s_.end_cells[0], hi = lo;
  for (const CellIndex& c : s_.end_cells)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], c[a]);
      hi[a] = std::max(hi[a], c[a]);
    }
  const uint64_t nx = uint64_t(hi.x - lo.x) + 1, ny = uint64_t(hi.y - lo.y) + 1;
  const uint64_t nz = uint64_t(hi.z - lo.z) + 1;
  for (RayEnd& r : s_.ray_ends) {
    const CellIndex& c = s_.end_cells[r.point];
    const uint64_t dense =
        (uint64_t(c.z - lo.z) * ny + uint64_t(c.y - lo.y)) * nx + uint64_t(c.x - lo.x);
    r.key |= dense << 1;  // the low bit already holds `hit`
  }
  int key_bits = 1;
  while (key_bits < 64 && (uint64_t(1) << key_bits) < 2 * nx * ny * nz) ++key_bits;
  radixSortByKey(s_.ray_ends, s_.sort_buffer, key_bits);

  const GridGeometry& geometry = map_.geometry();
  for (size_t begin = 0; begin < s_.ray_ends.size();) {
    size_t end = begin + 1;
    while (end < s_.ray_ends.size() && s_.ray_ends[end].key == s_.ray_ends[begin].key) ++end;
    EndGroup g;
    g.cell = s_.end_cells[s_.ray_ends[begin].point];
    g.hit = (s_.ray_ends[begin].key & 1) != 0;
    g.count = uint32_t(end - begin);
    // Two-pass statistics (Eq. 1) of the group, relative to the cell centre.
    const Eigen::Vector3d centre = geometry.cellCenter(g.cell);
    CellStats& stats = g.batch;
    stats.n = g.count;
    for (size_t i = begin; i < end; ++i) stats.mean += s_.ends[s_.ray_ends[i].point] - centre;
    stats.mean /= double(g.count);
    for (size_t i = begin; i < end; ++i) {
      const Eigen::Vector3d d = s_.ends[s_.ray_ends[i].point] - centre - stats.mean;
      stats.scatter += d * d.transpose();
    }
    g.mean_end = centre + stats.mean;
    if (!g.hit) stats = CellStats{};
    s_.groups.push_back(g);
    report_.cells_hit += g.hit;
    begin = end;
  }
}

// Step 3: count N_e, the rays crossing each cell without ending in it. Rays are split in
// contiguous chunks (neighbouring rays share cells) over threads with their own counters.
void ScanUpdater::traceFreeRays() {
  const bool per_point = options_.ray_mode == RayMode::PerPoint;
  const size_t rays = per_point ? s_.ends.size() : s_.groups.size();
  const size_t threads = std::max<size_t>(1, std::min<size_t>(options_.threads, rays / 256 + 1));
  if (s_.counts.size() < threads) s_.counts.resize(threads);
  for (ScanCounts& c : s_.counts) c.clear();

  const GridGeometry& geometry = map_.geometry();
  std::vector<size_t> visits(threads, 0);
  auto trace = [&](size_t t) {
    CountingWalker count(s_.counts[t]);
    const size_t begin = rays * t / threads, end = rays * (t + 1) / threads;
    for (size_t i = begin; i < end; ++i) {
      if (per_point) {
        count = walkRay(geometry, origin_, s_.ends[i], count);
      } else {
        count.setWeight(s_.groups[i].count);
        count = walkRay(geometry, origin_, s_.groups[i].mean_end, count);
      }
    }
    visits[t] = count.visits();
  };

  std::vector<std::exception_ptr> errors(threads);
  std::vector<std::thread> workers;
  for (size_t t = 1; t < threads; ++t)
    workers.emplace_back([&, t] {
      try {
        trace(t);
      } catch (...) {
        errors[t] = std::current_exception();
      }
    });
  try {
    trace(0);
  } catch (...) {
    errors[0] = std::current_exception();
  }
  for (std::thread& w : workers) w.join();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
  for (size_t t = 1; t < threads; ++t) {
    s_.counts[0].addAll(s_.counts[t]);
    s_.counts[t].clear();
  }
  report_.rays_cast = rays;
  for (size_t n : visits) report_.voxel_visits += n;
}

// Step 4: Eq. 12 once per touched cell, then the RCU merge of the hits.
void ScanUpdater::applyToMap() {
  auto& grid = map_.grid_;
  if (s_.counts.empty()) s_.counts.resize(1);
  ScanCounts& counts = s_.counts[0];
  // A cell with hits in this scan takes the hit update only (Eq. 12, N_p > 0).
  for (const EndGroup& g : s_.groups)
    if (g.hit)
      if (uint32_t* n = counts.find(g.cell)) *n = 0;

  // Allocate everything first, so the update below cannot fail half-way.
  std::vector<CellIndex> created_blocks;
  std::vector<NdtMap::Block*> map_blocks;
  try {
    map_blocks.reserve(counts.numBlocks());
    for (size_t i = 0; i < counts.numBlocks(); ++i) {
      bool created = false;
      map_blocks.push_back(&grid.getOrCreate(counts.blockIndex(i), &created));
      if (created) created_blocks.push_back(counts.blockIndex(i));
    }
    for (const EndGroup& g : s_.groups) {
      if (!g.hit) continue;
      bool created = false;
      grid.getOrCreate(blockOf(g.cell), &created);
      if (created) created_blocks.push_back(blockOf(g.cell));
    }
    map_.stats_.reserve(s_.groups.size());
  } catch (...) {
    for (const CellIndex& b : created_blocks) grid.erase(b);
    counts.clear();
    throw;
  }

  const double miss = map_.options().occupancy.missLogOdds();
  const double hit = map_.options().occupancy.hitLogOdds();
  for (size_t b = 0; b < counts.numBlocks(); ++b) {
    applyFreeCounts(counts.block(b), *map_blocks[b], miss);
    counts.zeroBlock(b);  // while it is in cache
  }
  counts.reset();
  BlockAccessor<NdtMap::Block> blocks(grid);
  for (const EndGroup& g : s_.groups) {
    if (!g.hit) continue;
    updateCell(blocks.getOrCreate(blockOf(g.cell)), offsetInBlock(g.cell), double(g.count) * hit,
               &g.batch);
    ++report_.cells_touched;
  }
}

// Eq. 12 for the cells of one block that rays crossed without a hit: the bulk of the
// update, so it avoids the general updateCell path for cells without statistics.
void ScanUpdater::applyFreeCounts(const CountBlock& counts, NdtMap::Block& block, double miss) {
  const double lo = map_.options().occupancy.logodds_min;
  const double hi = map_.options().occupancy.logodds_max;
  size_t touched = 0, created = 0;
  constexpr int kGroup = 8;  // 32 bytes of counters tested at once: most are zero
  for (int g = 0; g < kBlockCells; g += kGroup) {
    uint32_t any = 0;
    for (int k = 0; k < kGroup; ++k) any |= counts.count[g + k];
    if (any == 0) continue;
    for (int i = g; i < g + kGroup; ++i) {
      const uint32_t n = counts.count[i];
      if (n == 0) continue;
      ++touched;
      if (block.stats[i] != NdtMap::kNoStats) {
        updateCell(block, i, double(n) * miss, nullptr);
        continue;
      }
      if (!block.known[i]) {
        block.known.set(i);
        block.logodds[i] = 0.f;
        ++created;
      }
      block.logodds[i] = float(std::clamp(double(block.logodds[i]) + double(n) * miss, lo, hi));
    }
  }
  report_.cells_touched += touched;
  report_.cells_created += created;
  map_.num_cells_ += created;
}

void ScanUpdater::updateCell(NdtMap::Block& block, int offset, double delta_logodds,
                             const CellStats* batch) {
  if (!block.known[offset]) {
    block.known.set(offset);
    block.logodds[offset] = 0.f;
    ++map_.num_cells_;
    ++report_.cells_created;
  }
  const float logodds = map_.clampLogOdds(double(block.logodds[offset]) + delta_logodds);
  block.logodds[offset] = logodds;

  uint32_t& slot = block.stats[offset];
  auto& pool = map_.stats_;
  const bool had_gaussian = slot != NdtMap::kNoStats && pool.items[slot].hasGaussian();
  if (map_.options().occupancy.enabled && logodds <= 0.f) {
    // Observed empty: the Gaussian goes; later hits start a new one.
    if (slot != NdtMap::kNoStats) {
      pool.remove(slot);
      slot = NdtMap::kNoStats;
    }
  } else if (batch) {
    if (slot == NdtMap::kNoStats)
      slot = pool.add(*batch);
    else
      pool.items[slot].merge(*batch);
  }
  const bool has_gaussian = slot != NdtMap::kNoStats && pool.items[slot].hasGaussian();
  report_.gaussians_gained += !had_gaussian && has_gaussian;
  report_.gaussians_lost += had_gaussian && !has_gaussian;
}

}  // namespace ndtom
