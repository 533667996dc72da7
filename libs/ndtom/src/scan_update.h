// One scan's update of an NDT-OM (paper Sec. III): private to the library.
#pragma once

#include <Eigen/Core>
#include <array>
#include <atomic>
#include <utility>
#include <vector>

#include "ndtom/ndt_map.h"
#include "parallel.h"
#include "scan_counts.h"

namespace ndtom {

/// Rays that end in one cell: the unit of Eq. 12's N_p and of the per-hit-cell ray mode.
struct EndGroup {
  CellIndex cell;
  uint32_t begin;  ///< its rays are ray_ends[begin, begin + count), ends in sorted_ends
  uint32_t count;
  bool hit;
  Eigen::Vector3d mean;      ///< of the ray ends, relative to the cell centre (per-hit-cell mode)
  Eigen::Vector3d mean_end;  ///< the same in the world frame: that mode's ray end
};

/// What classification made of one input point.
enum class PointKind : uint8_t { kRejected, kTruncated, kHit };

/// Scratch memory reused from scan to scan (kept by the map, not part of its state).
struct ScanScratch {
  /// Per input point: its kind and, unless rejected, its ray end (the hit point, or the
  /// max-range end of a truncated ray, world frame) and that end's cell.
  std::vector<PointKind> kinds;
  std::vector<Eigen::Vector3d> ends;
  std::vector<CellIndex> end_cells;
  /// Where each used point's ray ends (a hit, or the max-range end of a truncated ray), as
  /// one word: its cell's key (block number * kBlockCells + offset in the block, times 2, plus
  /// 1 for a hit) above the point's index into `ends`. Sorted by key, the ends of a cell are
  /// together, a block's cells in a row and in offset order.
  std::vector<uint64_t> ray_ends, sort_buffer;
  std::vector<size_t> part_offsets;  ///< where each classification chunk's ends start in ray_ends
  std::vector<Eigen::Vector3d> sorted_ends;  ///< ends in ray_ends' order: groups read them in a row
  std::vector<EndGroup> groups;
  std::vector<ScanCounts> counts;         ///< one per tracing thread; counts[0] also gets the union
  size_t counts_used = 1;                 ///< tables filled by this scan's tracing (>= 1)
  std::vector<CountBlock*> other_counts;  ///< [block * (counts_used-1) + t-1], or nullptr
  std::vector<NdtMap::Block*> map_blocks;  ///< the map's block of each counts[0] block
  std::vector<size_t> new_blocks;          ///< counts[0] blocks the map lacks, to create
  std::vector<CellIndex> created_blocks;   ///< map blocks this scan created, for a rollback
  /// What one thread of the map update did; a cache line each, as threads count per cell.
  struct alignas(64) ApplyPart {
    size_t touched = 0, created = 0, gaussians_gained = 0, gaussians_lost = 0;
    size_t stats_bytes = 0;  ///< change of the map's statistics bytes (modulo 2^64)
  };
  std::vector<ApplyPart> apply_parts;
  /// A map block with hits in this scan: the unit of the hit update, owned by one thread.
  struct HitBlock {
    size_t first_group, last_group;  ///< from its first hit group to its last (in `groups`)
    NdtMap::Block* block;            ///< set by allocateForApply
    NdtMap::Block::Mask hits;        ///< its hit cells
    /// If its cells may gain statistics: an empty array with room for all the block will
    /// have, made before the map changes; its statistics move there. Else no capacity.
    std::vector<CellStats> grown;
  };
  std::vector<HitBlock> hit_blocks;
  std::vector<size_t> hit_part_starts;  ///< hit_blocks ranges of the hit threads
  WorkerPool pool;                      ///< the insertion's threads, kept while the map lives
};

class ScanUpdater {
 public:
  /// What the memory budget counts per point of a scan (classification, sorting and grouping
  /// buffers) and per block a scan adds (its counters, and the map's new block).
  static constexpr uint64_t kBytesPerPoint = sizeof(PointKind) + 2 * sizeof(Eigen::Vector3d) +
                                             sizeof(CellIndex) + 2 * sizeof(uint64_t) +
                                             sizeof(EndGroup);
  static constexpr uint64_t kBytesPerNewBlock =
      ScanCounts::kBytesPerBlock + BlockGrid<NdtMap::Block>::kBytesPerBlock;

  ScanUpdater(NdtMap& map, const InsertOptions& options, ScanScratch& scratch)
      : map_(map), options_(options), s_(scratch) {}

  InsertionReport run(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& origin);

 private:
  /// The points are cut in this many near-equal contiguous pieces: classification's threads
  /// take whole pieces and sum each one's ray lengths, by which the free-ray pass shares the
  /// rays among threads. Not fewer than the threads allowed.
  static constexpr size_t kRayPieces = 256;
  static_assert(kRayPieces >= size_t(InsertOptions::kMaxThreads), "a piece per thread");

  /// Memory budget, before classification: the map and the scan's per-point buffers.
  void checkBudgetForPoints(size_t points);
  /// Before tracing: the blocks of the hits (a lower bound of the blocks the scan adds) and
  /// their statistics; then limits the tracing tables to the blocks the budget leaves.
  void checkBudgetForEnds();
  void classifyPoints(const std::vector<Eigen::Vector3d>& points);
  std::pair<size_t, size_t> classifyChunk(size_t t) const;
  void groupEndsByCell();
  int keyEndsByBlockRank();
  /// The ray_ends word of used point `i` whose end is in cell `dense` (block number *
  /// kBlockCells + offset in the block).
  uint64_t rayEndWord(uint64_t dense, size_t i) const {
    const uint64_t key = dense << 1 | (s_.kinds[i] == PointKind::kHit ? 1u : 0u);
    return key << point_bits_ | i;
  }
  uint64_t keyOf(uint64_t ray_end) const { return ray_end >> point_bits_; }
  size_t pointOf(uint64_t ray_end) const { return size_t(ray_end & point_mask_); }
  void traceFreeRays();
  void applyToMap();
  void allocateForApply();
  PointKind classifyPoint(const Eigen::Vector3d& p, Eigen::Vector3d& end,
                          InsertionReport& report) const;
  void applyFreeCounts(size_t begin, size_t end, ScanScratch::ApplyPart& part);
  void applyHits(ScanScratch::HitBlock& hit_block, ScanScratch::ApplyPart& part);
  CellStats groupStats(const EndGroup& g) const;
  size_t threadsFor(size_t items, size_t min_items_per_thread) const;

  NdtMap& map_;
  const InsertOptions& options_;
  ScanScratch& s_;
  InsertionReport report_;
  Eigen::Vector3d origin_;
  CellIndex ends_lo_, ends_hi_;     ///< bounding box of the ray ends' cells
  bool group_means_ready_ = false;  ///< EndGroup::mean and mean_end are computed
  int point_bits_ = 1;              ///< low bits of a ray_ends word that hold the point
  uint64_t point_mask_ = 1;
  size_t classify_threads_ = 1, apply_threads_ = 1, hit_threads_ = 1;
  /// Per piece of the points, their rays' summed L1 lengths (what a walk costs).
  std::array<double, kRayPieces> piece_lengths_{};
  uint64_t budget_used_ = 0;             ///< map + this scan's buffers, as estimated so far (bytes)
  std::atomic<int64_t> blocks_left_{0};  ///< new blocks tracing may add (memory budget)
  size_t end_blocks_ = 0;                ///< distinct blocks of the ray ends
};

}  // namespace ndtom
