#include "scan_update.h"

#include <algorithm>
#include <stdexcept>

#include "ndtom/ray_dda.h"

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
  ends_.clear();
  ray_ends_.clear();
  ends_.reserve(points.size());
  ray_ends_.reserve(points.size());
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
    ray_ends_.push_back({geometry.cellOf(end), uint32_t(ends_.size()), hit});
    ends_.push_back(end);
    ++(hit ? report_.hits : report_.truncated);
  }
}

// Step 2: gather the ray ends per cell; a hit group's points give N_p and the batch that
// RCU merges into the cell (Eq. 2, 11).
void ScanUpdater::groupEndsByCell() {
  std::sort(ray_ends_.begin(), ray_ends_.end(), [](const RayEnd& a, const RayEnd& b) {
    if (a.cell != b.cell) return a.cell < b.cell;
    return a.hit < b.hit;
  });
  groups_.clear();
  std::vector<Eigen::Vector3d> relative;
  for (size_t begin = 0; begin < ray_ends_.size();) {
    size_t end = begin;
    while (end < ray_ends_.size() && ray_ends_[end].cell == ray_ends_[begin].cell &&
           ray_ends_[end].hit == ray_ends_[begin].hit)
      ++end;
    EndGroup g{ray_ends_[begin].cell, ray_ends_[begin].hit, uint32_t(end - begin), {}, {}};
    const Eigen::Vector3d centre = map_.geometry().cellCenter(g.cell);
    relative.clear();
    for (size_t i = begin; i < end; ++i) relative.push_back(ends_[ray_ends_[i].point] - centre);
    const CellStats stats = CellStats::fromPoints(relative);
    g.mean_end = centre + stats.mean;
    if (g.hit) g.batch = stats;
    groups_.push_back(g);
    begin = end;
  }
  report_.cells_hit = size_t(
      std::count_if(groups_.begin(), groups_.end(), [](const EndGroup& g) { return g.hit; }));
}

// Step 3: count N_e, the rays crossing each cell without ending in it.
void ScanUpdater::traceFreeRays() {
  free_counts_.clear();
  BlockAccessor<CountBlock> counts(free_counts_);
  const GridGeometry& geometry = map_.geometry();
  uint32_t weight = 1;
  size_t visits = 0;
  auto count_cell = [&](const CellIndex& c) {
    counts.getOrCreate(blockOf(c)).count[offsetInBlock(c)] += weight;
    ++visits;
    return true;
  };
  if (options_.ray_mode == RayMode::PerPoint) {
    for (const Eigen::Vector3d& end : ends_) traverseRay(geometry, origin_, end, count_cell);
    report_.rays_cast = ends_.size();
  } else {
    for (const EndGroup& g : groups_) {
      weight = g.count;
      traverseRay(geometry, origin_, g.mean_end, count_cell);
    }
    report_.rays_cast = groups_.size();
  }
  report_.voxel_visits = visits;
}

// Step 4: Eq. 12 once per touched cell, then the RCU merge of the hits.
void ScanUpdater::applyToMap() {
  auto& grid = map_.grid_;
  // A cell with hits in this scan takes the hit update only (Eq. 12, N_p > 0).
  for (const EndGroup& g : groups_) {
    if (!g.hit) continue;
    if (CountBlock* b = free_counts_.find(blockOf(g.cell))) b->count[offsetInBlock(g.cell)] = 0;
  }

  // Allocate everything first, so the update below cannot fail half-way.
  std::vector<CellIndex> created_blocks;
  std::vector<std::pair<const CountBlock*, NdtMap::Block*>> free_blocks;
  try {
    free_blocks.reserve(free_counts_.size());
    created_blocks.reserve(free_counts_.size() + groups_.size());
    for (const auto& [index, counts] : free_counts_.blocks()) {
      bool created = false;
      free_blocks.emplace_back(counts.get(), &grid.getOrCreate(index, &created));
      if (created) created_blocks.push_back(index);
    }
    for (const EndGroup& g : groups_) {
      bool created = false;
      grid.getOrCreate(blockOf(g.cell), &created);
      if (created) created_blocks.push_back(blockOf(g.cell));
    }
    map_.stats_.reserve(groups_.size());
  } catch (...) {
    for (const CellIndex& b : created_blocks) grid.erase(b);
    throw;
  }

  const OccupancyOptions& occupancy = map_.options().occupancy;
  const double miss = occupancy.missLogOdds();
  const double hit = occupancy.hitLogOdds();
  for (const auto& [counts, block] : free_blocks) {
    for (int i = 0; i < kBlockCells; ++i) {
      if (counts->count[i] == 0) continue;
      updateCell(*block, i, double(counts->count[i]) * miss, nullptr);
      ++report_.cells_touched;
    }
  }
  BlockAccessor<NdtMap::Block> blocks(grid);
  for (const EndGroup& g : groups_) {
    if (!g.hit) continue;
    updateCell(blocks.getOrCreate(blockOf(g.cell)), offsetInBlock(g.cell), double(g.count) * hit,
               &g.batch);
    ++report_.cells_touched;
  }
  free_counts_.clear();
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
