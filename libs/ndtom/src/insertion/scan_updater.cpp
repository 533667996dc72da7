#include "insertion/scan_updater.h"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "insertion/point_shares.h"
#include "ndtom_internal/input_file.h"
#include "support/stage_clock.h"

namespace ndtom {

namespace {

ScanScratch& scratchOf(NdtMap& map) {
  auto& scratch = MapInternals::scratch(map);
  if (!scratch) scratch.reset(new ScanScratch);
  return *scratch;
}

}  // namespace

ScanUpdater::ScanUpdater(NdtMap& map, const ScanOptions& options, const ScanPart* part)
    : map_(map), options_(options), s_(scratchOf(map)), part_(part),
      revision_before_(map.revision()) {
  MapInternals::touch(map_);
}

InsertionReport ScanUpdater::run(const std::vector<Eigen::Vector3d>& points,
                                 const Eigen::Vector3d& origin) {
  StageClock clock(options_.profile);
  clock.next("setup");
  // Any failure before one of this scan's exchanges, from here on, is told to the others.
  const bool occupancy = map_.options().occupancy.enabled;
  const bool ray_per_group = occupancy && options_.ray_mode == RayMode::PerHitCell;
  // Per-point rays need no groups to be cast: a process sharing the rays out classifies a
  // share of the points and walks their rays, and the owners update the hits (a second
  // exchange agrees that every process could). Per-hit-cell rays are cast to the groups, so
  // there every process classifies and groups every end.
  const bool share_points = part_ && part_->exchange && occupancy && !ray_per_group;
  s_.free_counts.exchanges_left = !part_ || !part_->exchange || !occupancy ? 0
                                  : share_points                          ? 2
                                                                          : 1;
  struct FailureNotice {
    ScanUpdater& updater;
    const int exceptions = std::uncaught_exceptions();
    ~FailureNotice() {
      if (std::uncaught_exceptions() > exceptions) updater.tellOthersOfFailure();
    }
  } notice{*this};
  validate(options_);
  if (!map_.geometry().inRange(origin))
    throw std::invalid_argument("insertScan: sensor origin is not finite or outside the grid");
  if (points.size() > UINT32_MAX)
    throw std::invalid_argument("insertScan: more than 2^32 points in one scan; split it");
  InsertionReport report;
  report.points_in = points.size();
  s_.free_counts.reset();
  checkBudgetForPoints(points.size());
  const ScanContext scan{map_.geometry(), options_, origin, s_.pool};
  const TileOwnership* owned = part_ ? &part_->owned : nullptr;

  // Nothing below touches the map until applyToMap(), which cannot fail half-way.
  try {
    if (share_points) {
      insertSharingPoints(scan, points, report, clock);
    } else {
      clock.next("classify");
      classifyPoints(scan, points, s_.points, report);
      // Without sharing the points, a process with per-point rays sorts and groups only its
      // tiles' hits.
      clock.next("sort");
      sortRayEnds(scan, s_.points, ray_per_group ? nullptr : owned, s_.ray_ends);
      clock.next("group");
      groupEnds(scan, s_.points, s_.ray_ends,
                ray_per_group ? GroupMeans::Compute : GroupMeans::Skip, s_.groups, report);
      if (owned) dropHitsOutside(*owned);
      checkBudgetForEnds(report);
      clock.next("trace");
      if (occupancy) traceFreeRaysInBudget(scan, s_.points, report);
    }
    clock.next("apply");
    const MapChange change = applyToMap(scan, map_.options(), s_.groups, s_.free_counts,
                                        MapInternals::grid(map_), s_.apply, report);
    MapInternals::countBlocks(map_, change.cells_created, change.stats_bytes);
    clock.next("record");
    recordStatsChanges();
  } catch (const MemoryBudgetError&) {
    for (ScanCounts& c : s_.free_counts.tables) c.releaseMemory();  // may hold the budget's worth
    throw;
  } catch (...) {
    for (ScanCounts& c : s_.free_counts.tables) c.clear();  // the next scan starts from zero
    throw;
  }
  return report;
}

void ScanUpdater::insertSharingPoints(const ScanContext& scan,
                                      const std::vector<Eigen::Vector3d>& points,
                                      InsertionReport& report, StageClock& clock) {
  const TileOwnership& owned = part_->owned;
  clock.next("classify");
  const auto [first, last] =
      pointShare(scan, points.data(), points.size(), size_t(owned.ranks), size_t(owned.rank));
  classifyPoints(scan, points.data() + first, last - first, s_.points, report);
  // Tracing comes before the hits are known, so its blocks are limited by what the points
  // leave of the budget, and counted with the hits' below.
  const int64_t blocks_for_tracing =
      int64_t((std::max(options_.memory_budget, budget_used_) - budget_used_) / kBytesPerNewBlock);
  blocks_left_.store(blocks_for_tracing, std::memory_order_relaxed);
  s_.groups.hit_blocks.clear();  // the last scan's: not counted in a budget error
  clock.next("trace");
  traceFreeRaysInBudget(scan, s_.points, report);  // the exchange: hits and counts
  budget_used_ += uint64_t(blocks_for_tracing - blocks_left_.load(std::memory_order_relaxed)) *
                  kBytesPerNewBlock;
  clock.next("sort");
  listHits(scan, s_.free_counts.hits_from, s_.own_hits);
  sortRayEnds(scan, s_.own_hits, nullptr, s_.ray_ends);
  clock.next("group");
  groupEnds(scan, s_.own_hits, s_.ray_ends, GroupMeans::Skip, s_.groups, report);
  checkBudgetForEnds(report);
  agreeWithOthers();
}

void ScanUpdater::agreeWithOthers() {
  std::vector<std::vector<uint32_t>> nothing(size_t(part_->owned.ranks)), ignored;
  exchangeOrStop(*part_->exchange, s_.free_counts, nothing, ignored);
}

void ScanUpdater::recordStatsChanges() noexcept {
  StatsChanges& changes = MapInternals::statsChanges(map_);
  try {
    std::vector<BlockCells>& blocks = changes.blocks;
    blocks.clear();
    for (const HitBlock& h : s_.groups.hit_blocks)
      blocks.push_back({blockOf(s_.groups.blockCell(h)), h.hits});
    for (const auto& cells : s_.apply.emptied)
      for (const ApplyBuffers::EmptiedCell& c : cells) {
        BlockCells emptied{c.block, {}};
        emptied.cells[size_t(c.offset >> 6)] = uint64_t(1) << (c.offset & 63);
        blocks.push_back(emptied);
      }
    if (!s_.apply.emptied_complete) return;  // left unknown
    changes.from = revision_before_;
    changes.to = map_.revision();
  } catch (...) {  // out of memory: left unknown, followers rebuild
    changes.from = changes.to = 0;
  }
}

void ScanUpdater::tellOthersOfFailure() noexcept {
  // The others wait in this scan's next exchange, and stop there: one call. A process whose
  // exchange itself threw does not call it again.
  if (!part_ || !part_->exchange || s_.free_counts.exchanges_left <= 0) return;
  s_.free_counts.exchanges_left = 0;
  try {
    std::vector<std::vector<uint32_t>> none, ignored;
    part_->exchange->exchange(true, none, ignored);
  } catch (...) {  // the scan's own error is the one to report
  }
}

void ScanUpdater::dropHitsOutside(const TileOwnership& owned) {
  // Other processes update these cells; the groups stay, as per-hit-cell rays start from them.
  // (With per-point rays only owned hits were grouped: nothing to drop.)
  std::vector<HitBlock>& hits = s_.groups.hit_blocks;
  hits.erase(std::remove_if(hits.begin(), hits.end(),
                            [&](const HitBlock& h) {
                              return !owned.ownsBlock(blockOf(s_.groups.blockCell(h)));
                            }),
             hits.end());
}

void ScanUpdater::checkBudgetForPoints(size_t points) {
  budget_used_ = map_.memoryBytes() + points * kBytesPerPoint;
  if (budget_used_ > options_.memory_budget)
    throw MemoryBudgetError("insertScan: a scan of " + std::to_string(points) +
                                " points (the map takes " + megabytes(map_.memoryBytes()) + ")",
                            budget_used_, options_.memory_budget);
}

void ScanUpdater::checkBudgetForEnds(const InsertionReport& report) {
  // The hit cells' blocks and statistics, counted by groupEnds: no pass over the groups.
  const size_t end_blocks = s_.groups.hit_blocks.size();
  budget_used_ += report.cells_hit * sizeof(CellStats) + end_blocks * kBytesPerNewBlock;
  const uint64_t budget = options_.memory_budget;
  if (budget_used_ > budget) {
    char resolution[32];
    std::snprintf(resolution, sizeof(resolution), "%g", map_.options().resolution);
    throw MemoryBudgetError("insertScan: a scan whose hits lie in " + std::to_string(end_blocks) +
                                " blocks of 8^3 cells (resolution " + resolution + " m)",
                            budget_used_, budget);
  }
  blocks_left_.store(int64_t((budget - budget_used_) / kBytesPerNewBlock),
                     std::memory_order_relaxed);
}

void ScanUpdater::traceFreeRaysInBudget(const ScanContext& scan, const ClassifiedPoints& points,
                                        InsertionReport& report) {
  try {
    traceFreeRays(scan, part_, points, s_.groups, blocks_left_, s_.free_counts, report);
  } catch (const BlockLimitReached&) {
    char resolution[32];
    std::snprintf(resolution, sizeof(resolution), "%g", map_.options().resolution);
    const size_t end_blocks = s_.groups.hit_blocks.size();
    size_t blocks = end_blocks;
    for (size_t t = 0; t < s_.free_counts.used; ++t) blocks += s_.free_counts.tables[t].numBlocks();
    throw MemoryBudgetError(
        "insertScan: a scan whose rays cross more than " + std::to_string(blocks) +
            " blocks of 8^3 cells (resolution " + resolution + " m)",
        budget_used_ + (blocks - end_blocks + 1) * kBytesPerNewBlock, options_.memory_budget);
  }
}

}  // namespace ndtom
