// NDT Occupancy Map (Saarinen et al., ICRA 2013): a sparse grid whose cells hold exact
// recursive Gaussian statistics (Sec. III-A) and an occupancy log-odds (Sec. III-C).
//
// Threading contract: const member functions may run concurrently with each other; any
// non-const call (insertScan, merge, clear, assignment) needs exclusive access.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <type_traits>
#include <vector>

#include "ndtom/map/block_grid.h"
#include "ndtom/map/cell_index.h"
#include "ndtom/map/cell_stats.h"
#include "ndtom/map/gaussian.h"
#include "ndtom/map/insertion_report.h"
#include "ndtom/map/options.h"
#include "ndtom/map/stats_changes.h"

namespace ndtom {

struct MapBlock;      // src/map/map_block.h
struct MapInternals;  // src/map/map_internals.h
struct ScanScratch;   // src/insertion/scan_updater.h
/// Frees insertion's scratch where its type is known (insertion/), so the map's own code
/// needs none of insertion's headers.
struct ScanScratchDeleter {
  void operator()(ScanScratch* scratch) const;
};

/// The covariance a cell's Gaussian carries: the exact sample covariance (Eq. 3), or that
/// with its eigenvalues floored (MapOptions::regularization), as the likelihood and the
/// registration use it.
enum class Covariance : uint8_t { Regularized, Exact };

/// Read-only view of one known cell.
struct CellView {
  CellIndex index;
  float logodds = 0;                 ///< occupancy log-odds (Eq. 12), clamped
  /// Points merged so far, null if none; its relative_mean is from the cell centre (a
  /// Gaussian's mean is in the world frame).
  const CellStats* stats = nullptr;
};

class NdtMap {
 public:
  /// Throws std::invalid_argument if the options are invalid.
  explicit NdtMap(const MapOptions& options = {});
  NdtMap(const NdtMap& other);
  NdtMap& operator=(const NdtMap& other);
  NdtMap(NdtMap&&) noexcept;
  NdtMap& operator=(NdtMap&&) noexcept;
  ~NdtMap();

  const MapOptions& options() const { return options_; }
  const GridGeometry& geometry() const { return geometry_; }

  // --- Insertion (paper Sec. III) --------------------------------------------------------

  /// Inserts one scan: points in the world frame, seen from `sensor_origin`. Bad points are
  /// skipped and counted; a bad origin throws std::invalid_argument. If anything throws, the
  /// map is left as it was before the call.
  InsertionReport insertScan(const std::vector<Eigen::Vector3d>& points,
                             const Eigen::Vector3d& sensor_origin);
  InsertionReport insertScan(const std::vector<Eigen::Vector3d>& points,
                             const Eigen::Vector3d& sensor_origin, const ScanOptions& options);
  // A distributed build's process inserts with insertScanPart (scale/distributed_insert.h).

  // --- Queries: const, never allocate, never change the map -------------------------------

  bool isEmpty() const { return num_cells_ == 0; }
  size_t numCells() const { return num_cells_; }  ///< cells ever observed and not cleared
  size_t numBlocks() const;  ///< blocks of kBlockEdge³ cells held
  size_t numGaussians() const;                    ///< cells with N ≥ 3
  size_t numOccupied() const;  ///< cells cellState() (map_queries.h) calls occupied

  [[nodiscard]] std::optional<CellView> cell(const CellIndex& index) const;
  /// Cell at a point; nullopt if unknown, non-finite or outside the supported range.
  [[nodiscard]] std::optional<CellView> cellAt(const Eigen::Vector3d& point) const;
  /// p(m | z_1:t) of the cell at `point`; nullopt where nothing is known.
  [[nodiscard]] std::optional<double> occupancyProbability(const Eigen::Vector3d& point) const;
  /// World-frame Gaussian of a cell with N ≥ 3, its covariance regularised or exact.
  [[nodiscard]] std::optional<Gaussian> gaussian(
      const CellIndex& index, Covariance covariance = Covariance::Regularized) const;
  [[nodiscard]] Gaussian gaussianOf(const CellView& cell,
                                    Covariance covariance = Covariance::Regularized) const;

  /// f(const CellView&) for every known cell, block by block.
  template <class F>
  void forEachCell(F&& f) const;
  /// The same in ascending block order: deterministic, whatever the insertion history.
  template <class F>
  void forEachCellOrdered(F&& f) const;
  /// f(const Gaussian&) for every cell with N ≥ 3.
  template <class F>
  void forEachGaussian(F&& f, Covariance covariance = Covariance::Regularized) const;

  /// Most points a scan can have under a memory budget of `budget` bytes: each takes ~160
  /// bytes of buffers while it is inserted. For readers, to refuse larger scans before
  /// allocating them.
  [[nodiscard]] static uint64_t maxScanPoints(uint64_t budget);

  /// Heap bytes used by cells, blocks, index and statistics. O(1): the statistics' share is
  /// kept up to date as they change (the memory budget reads it before every scan).
  size_t memoryBytes() const;
  /// The same, counted block by block: for tests of the bookkeeping.
  size_t memoryBytesCounted() const;

  /// Changes with every call that may change the cells (insertion, setCell, merge, clear);
  /// unique across maps, and shared by copies. Caches derived from a map (the registration
  /// pyramid) compare it to know when to rebuild.
  uint64_t revision() const { return revision_; }
  /// The cells the last insertScan() may have changed, between two revisions (from == 0
  /// after any other change, or a failed insertion). Not copied with the map.
  const StatsChanges& lastStatsChanges() const { return stats_changes_; }

  // --- Map algebra ------------------------------------------------------------------------

  /// Adds a map built from other data (same resolution, else std::invalid_argument):
  /// Gaussians by RCU, log-odds summed and clamped to this map's bounds. Throws
  /// MemoryBudgetError, the map unchanged, if the blocks it adds do not fit the budget.
  void merge(const NdtMap& other);

  /// A map `factor` times coarser (Sec. III-B): each coarse cell is the RCU merge of the fine
  /// cells inside it; its log-odds is the largest of theirs (occupied if any part is).
  [[nodiscard]] NdtMap coarsened(int factor) const;

  void clear();

  /// Calls f(coordinates) for every block of kBlockEdge³ cells (in no particular order).
  template <class F>
  void forEachBlock(F&& f) const {
    for (const auto& entry : grid_.blocks()) f(entry.first);
  }
  // Moving blocks between maps (the out-of-core map's tiles): scale/block_moves.h.

  // --- Low level: restoring a map from storage ------------------------------------------

  /// Sets one cell as given (used by loaders); the log-odds is clamped to the bounds, the
  /// statistics' mean is cell-centred. Returns whether the cell was unknown before. Throws,
  /// leaving the map unchanged, std::invalid_argument naming the problem if the cell breaks
  /// the rule of cell_rules.h (what saving writes and loading accepts), or MemoryBudgetError
  /// if a new block would take the map over scan.memory_budget.
  bool setCell(const CellIndex& index, float logodds, const CellStats& stats);
  /// Frees the spare room setCell() leaves in the blocks' statistics arrays (they grow one
  /// cell at a time); loaders and the map algebra call it when done.
  void shrinkToFit();

 private:
  friend struct MapInternals;  // insertion, block moves and spill files build blocks directly

  /// The templates above reach the (private) blocks through these: visit(f, cell) per cell.
  using CellCallback = void (*)(void* f, const CellView& cell);
  template <class F>
  static void callWith(void* f, const CellView& cell) {
    (*static_cast<std::remove_reference_t<F>*>(f))(cell);
  }
  template <class F>
  static void* erase(F& f) {
    return const_cast<void*>(static_cast<const void*>(&f));
  }
  void visitCells(CellCallback visit, void* f) const;
  void visitCellsOrdered(CellCallback visit, void* f) const;

  float clampLogOdds(double l) const;
  /// Half the cell edge: the box the cell-centred means stay in (CellStats::clampMean).
  double halfCell() const { return 0.5 * options_.resolution; }
  /// Throws MemoryBudgetError unless `new_blocks` more blocks fit the memory budget.
  void checkRoomForBlocks(size_t new_blocks, const char* what) const;
  void touch();  ///< a new revision()

  MapOptions options_;
  GridGeometry geometry_;
  BlockGrid<MapBlock> grid_;
  size_t num_cells_ = 0;
  size_t stats_bytes_ = 0;  ///< statsBytes() summed over the blocks
  uint64_t revision_ = 0;
  StatsChanges stats_changes_;
  /// Insertion's buffers and threads, made on first use: not part of the map's value, never
  /// copied.
  std::unique_ptr<ScanScratch, ScanScratchDeleter> scratch_;
};

// --- Template implementations ------------------------------------------------------------

template <class F>
void NdtMap::forEachCell(F&& f) const {
  visitCells(&callWith<F>, erase(f));
}

template <class F>
void NdtMap::forEachCellOrdered(F&& f) const {
  visitCellsOrdered(&callWith<F>, erase(f));
}

template <class F>
void NdtMap::forEachGaussian(F&& f, Covariance covariance) const {
  forEachCell([&](const CellView& c) {
    if (c.stats && c.stats->hasGaussian()) f(gaussianOf(c, covariance));
  });
}

}  // namespace ndtom
