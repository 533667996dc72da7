// One scan's update of an NDT-OM (paper Sec. III): private to the library. The stages are the
// other files of insertion/, each a function from named inputs to a named output;
// ScanUpdater::run calls them in order and keeps the memory budget.
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <vector>

#include "insertion/apply_to_map.h"
#include "insertion/classify_points.h"
#include "insertion/end_groups.h"
#include "insertion/free_rays.h"
#include "insertion/ray_ends.h"
#include "insertion/scan_counts.h"
#include "insertion/scan_part.h"
#include "map/map_internals.h"
#include "ndtom/map/ndt_map.h"
#include "support/parallel.h"
#include "support/stage_clock.h"

namespace ndtom {

/// What insertion keeps from scan to scan (held by the map, not part of its value): the
/// stages' outputs, whose buffers are reused, and the threads.
struct ScanScratch {
  ClassifiedPoints points;  ///< 1. what each point is, its ray end and end cell
  /// A distributed build's process sharing the points out: the hits in its own tiles, of
  /// all processes' shares (sorted and grouped in place of `points`).
  ClassifiedPoints own_hits;
  SortedRayEnds ray_ends;   ///< 2. the ray ends keyed by cell and sorted
  EndGroups groups;         ///< 3. the ray ends per cell
  FreeCounts free_counts;   ///< 4. N_e per cell
  ApplyBuffers apply;       ///< 5. the map update's buffers
  WorkerPool pool;          ///< the insertion's threads, kept while the map lives
};

class ScanUpdater {
 public:
  /// What the memory budget counts per point of a scan (classification, sorting and grouping
  /// buffers) and per block a scan adds (its counters, and the map's new block).
  static constexpr uint64_t kBytesPerPoint = sizeof(PointKind) + 2 * sizeof(Eigen::Vector3d) +
                                             sizeof(CellIndex) + 2 * sizeof(uint64_t) +
                                             sizeof(EndGroup);
  static constexpr uint64_t kBytesPerNewBlock =
      ScanCounts::kBytesPerBlock + BlockGrid<MapBlock>::kBytesPerBlock;

  /// Starts a new revision of the map. `part`: a distributed build's process, which changes
  /// only its own tiles' cells; nullptr: all cells change.
  ScanUpdater(NdtMap& map, const ScanOptions& options, const ScanPart* part = nullptr);

  InsertionReport run(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& origin);

 private:
  /// After a failure before this scan's count exchange: tells the other processes (which
  /// then fail the scan too), so that none waits for this one.
  void tellOthersOfFailure() noexcept;
  /// A distributed build's process: forgets the hits in other processes' tiles.
  void dropHitsOutside(const TileOwnership& owned);
  /// Memory budget, before classification: the map and the scan's per-point buffers.
  void checkBudgetForPoints(size_t points);
  /// Before tracing: the blocks of the hits (a lower bound of the blocks the scan adds) and
  /// their statistics; then limits the tracing tables to the blocks the budget leaves.
  void checkBudgetForEnds(const InsertionReport& report);
  /// After a successful update: the cells it may have changed (NdtMap::lastStatsChanges()).
  void recordStatsChanges() noexcept;
  /// traceFreeRays of `points`, throwing MemoryBudgetError if its tables would pass the budget.
  void traceFreeRaysInBudget(const ScanContext& scan, const ClassifiedPoints& points,
                             InsertionReport& report);
  /// The stages up to the update for a process that classifies its share of the points,
  /// walks their rays, and groups the hits all processes classified in its tiles.
  void insertSharingPoints(const ScanContext& scan, const std::vector<Eigen::Vector3d>& points,
                           InsertionReport& report, StageClock& clock);
  /// The exchange after the hits are grouped and checked against the budget: throws
  /// std::runtime_error if another process failed.
  void agreeWithOthers();

  NdtMap& map_;
  const ScanOptions& options_;
  ScanScratch& s_;
  const ScanPart* part_;
  uint64_t revision_before_;  ///< the map's, before this scan
  uint64_t budget_used_ = 0;             ///< map + this scan's buffers, as estimated so far (bytes)
  std::atomic<int64_t> blocks_left_{0};  ///< new blocks tracing may add (memory budget)
};

}  // namespace ndtom
