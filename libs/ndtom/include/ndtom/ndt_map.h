// NDT Occupancy Map (Saarinen et al., ICRA 2013): a sparse grid whose cells hold exact
// recursive Gaussian statistics (Sec. III-A) and an occupancy log-odds (Sec. III-C).
//
// Threading contract: const member functions may run concurrently with each other; any
// non-const call (insertScan, merge, clear, assignment) needs exclusive access.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <bitset>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "ndtom/block_grid.h"
#include "ndtom/cell_index.h"
#include "ndtom/cell_stats.h"
#include "ndtom/gaussian.h"
#include "ndtom/insertion_report.h"
#include "ndtom/options.h"

namespace ndtom {

struct ScanScratch;

/// Read-only view of one known cell.
struct CellView {
  CellIndex index;
  float logodds = 0;                 ///< occupancy log-odds (Eq. 12), clamped
  const CellStats* stats = nullptr;  ///< points merged so far (cell-centred mean); null if none
};

class NdtMap {
 public:
  /// Throws std::invalid_argument if the options are invalid.
  explicit NdtMap(const MapOptions& options = {});
  NdtMap(const NdtMap& other);
  NdtMap& operator=(const NdtMap& other);
  NdtMap(NdtMap&&) noexcept = default;
  NdtMap& operator=(NdtMap&&) noexcept = default;

  const MapOptions& options() const { return options_; }
  const GridGeometry& geometry() const { return geometry_; }

  // --- Insertion (paper Sec. III) --------------------------------------------------------

  /// Inserts one scan: points in the world frame, seen from `sensor_origin`. Bad points are
  /// skipped and counted; a bad origin throws std::invalid_argument. If anything throws, the
  /// map is left as it was before the call.
  InsertionReport insertScan(const std::vector<Eigen::Vector3d>& points,
                             const Eigen::Vector3d& sensor_origin);
  InsertionReport insertScan(const std::vector<Eigen::Vector3d>& points,
                             const Eigen::Vector3d& sensor_origin, const InsertOptions& options);

  // --- Queries: const, never allocate, never change the map -------------------------------

  bool isEmpty() const { return num_cells_ == 0; }
  size_t numCells() const { return num_cells_; }  ///< cells ever observed and not cleared
  size_t numGaussians() const;                    ///< cells with N ≥ 3
  size_t numOccupied() const;  ///< cells cellState() (map_queries.h) calls occupied

  std::optional<CellView> cell(const CellIndex& index) const;
  /// Cell at a point; nullopt if unknown, non-finite or outside the supported range.
  std::optional<CellView> cellAt(const Eigen::Vector3d& point) const;
  /// p(m | z_1:t) of the cell at `point`; nullopt where nothing is known.
  std::optional<double> occupancyProbability(const Eigen::Vector3d& point) const;
  /// World-frame Gaussian of a cell with N ≥ 3, its covariance regularised or exact.
  std::optional<Gaussian> gaussian(const CellIndex& index, bool regularized = true) const;
  Gaussian gaussianOf(const CellView& cell, bool regularized = true) const;

  /// f(const CellView&) for every known cell, block by block.
  template <class F>
  void forEachCell(F&& f) const;
  /// The same in ascending block order: deterministic, whatever the insertion history.
  template <class F>
  void forEachCellOrdered(F&& f) const;
  /// f(const Gaussian&) for every cell with N ≥ 3.
  template <class F>
  void forEachGaussian(F&& f, bool regularized = true) const;

  /// Most points a scan can have under a memory budget of `budget` bytes: each takes ~160
  /// bytes of buffers while it is inserted. For readers, to refuse larger scans before
  /// allocating them.
  static uint64_t maxScanPoints(uint64_t budget);

  /// Heap bytes used by cells, blocks, index and statistics. O(1): the statistics' share is
  /// kept up to date as they change (the memory budget reads it before every scan).
  size_t memoryBytes() const;
  /// The same, counted block by block: for tests of the bookkeeping.
  size_t memoryBytesCounted() const;

  /// Changes with every call that may change the cells (insertion, setCell, merge, clear);
  /// unique across maps, and shared by copies. Caches derived from a map (the registration
  /// pyramid) compare it to know when to rebuild.
  uint64_t revision() const { return revision_; }

  // --- Map algebra ------------------------------------------------------------------------

  /// Adds a map built from other data (same resolution, else std::invalid_argument):
  /// Gaussians by RCU, log-odds summed and clamped to this map's bounds. Throws
  /// MemoryBudgetError, the map unchanged, if the blocks it adds do not fit the budget.
  void merge(const NdtMap& other);

  /// A map `factor` times coarser (Sec. III-B): each coarse cell is the RCU merge of the fine
  /// cells inside it; its log-odds is the largest of theirs (occupied if any part is).
  NdtMap coarsened(int factor) const;

  void clear();

  // --- Low level: restoring a map from storage ------------------------------------------

  /// Sets one cell as given (used by loaders); the log-odds is clamped to the bounds, the
  /// statistics' mean is cell-centred. Returns whether the cell was unknown before. Throws,
  /// leaving the map unchanged, std::invalid_argument naming the problem if the cell breaks
  /// the rule of cell_rules.h (what saving writes and loading accepts), or MemoryBudgetError
  /// if a new block would take the map over insertion.memory_budget.
  bool setCell(const CellIndex& index, float logodds, const CellStats& stats);
  /// Frees the spare room setCell() leaves in the blocks' statistics arrays (they grow one
  /// cell at a time); loaders and the map algebra call it when done.
  void shrinkToFit();

 private:
  /// A block's cells, with the statistics of the few that have some packed in offset order:
  /// most known cells are free space, so a per-cell slot would cost more than the cells.
  struct Block {
    static constexpr int kWords = kBlockCells / 64;
    using Mask = std::array<uint64_t, kWords>;

    std::array<float, kBlockCells> logodds;
    std::bitset<kBlockCells> known;
    Mask has_stats{};              ///< bit i: cell i has statistics
    std::vector<CellStats> stats;  ///< of the cells in has_stats, in offset order

    Block() { logodds.fill(0.f); }
    bool hasStats(int i) const { return (has_stats[i >> 6] >> (i & 63)) & 1; }
    /// Position of cell i's statistics in `stats`: how many cells before it have some.
    size_t statsPos(int i) const {
      size_t pos = 0;
      for (int w = 0; w < (i >> 6); ++w) pos += size_t(__builtin_popcountll(has_stats[w]));
      const uint64_t below = (uint64_t(1) << (i & 63)) - 1;
      return pos + size_t(__builtin_popcountll(has_stats[i >> 6] & below));
    }
    const CellStats* statsOf(int i) const { return hasStats(i) ? &stats[statsPos(i)] : nullptr; }
    /// Drops cell i's statistics (it has some); never allocates. Returns whether they were a
    /// Gaussian.
    bool eraseStats(int i);
  };

  /// Insertion's reusable buffers: owned, never copied, not part of the map's value.
  class Scratch {
   public:
    Scratch();
    ~Scratch();
    Scratch(const Scratch&) : Scratch() {}
    Scratch& operator=(const Scratch&) { return *this; }
    Scratch(Scratch&&) noexcept;
    Scratch& operator=(Scratch&&) noexcept;
    ScanScratch& get() { return *p_; }

   private:
    std::unique_ptr<ScanScratch> p_;
  };

  friend class ScanUpdater;
  friend struct ScanScratch;

  template <class F>
  void forEachCellOfBlock(const CellIndex& block_index, const Block& block, F& f) const;

  float clampLogOdds(double l) const;
  /// Heap bytes of one block's statistics array (memoryBytes() counts them).
  static size_t statsBytes(const std::vector<CellStats>& stats);
  /// Half the cell edge: the box the cell-centred means stay in (CellStats::clampMean).
  double halfCell() const { return 0.5 * options_.resolution; }
  /// Throws MemoryBudgetError unless `new_blocks` more blocks fit the memory budget.
  void checkRoomForBlocks(size_t new_blocks, const char* what) const;
  void touch();  ///< a new revision()

  MapOptions options_;
  GridGeometry geometry_;
  BlockGrid<Block> grid_;
  size_t num_cells_ = 0;
  size_t stats_bytes_ = 0;  ///< statsBytes() summed over the blocks
  uint64_t revision_ = 0;
  Scratch scratch_;
};

// --- Template implementations ------------------------------------------------------------

template <class F>
void NdtMap::forEachCellOfBlock(const CellIndex& block_index, const Block& block, F& f) const {
  if (block.known.none()) return;
  const CellStats* next = block.stats.data();  // cells with statistics come in offset order
  for (int i = 0; i < kBlockCells; ++i) {
    if (!block.known[i]) continue;
    f(CellView{cellOf(block_index, i), block.logodds[i], block.hasStats(i) ? next++ : nullptr});
  }
}

template <class F>
void NdtMap::forEachCell(F&& f) const {
  for (const auto& [block_index, block] : grid_.blocks())
    forEachCellOfBlock(block_index, *block, f);
}

template <class F>
void NdtMap::forEachCellOrdered(F&& f) const {
  std::vector<std::pair<CellIndex, const Block*>> blocks;
  blocks.reserve(grid_.size());
  for (const auto& [block_index, block] : grid_.blocks())
    blocks.emplace_back(block_index, block.get());
  std::sort(blocks.begin(), blocks.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [block_index, block] : blocks) forEachCellOfBlock(block_index, *block, f);
}

template <class F>
void NdtMap::forEachGaussian(F&& f, bool regularized) const {
  forEachCell([&](const CellView& c) {
    if (c.stats && c.stats->hasGaussian()) f(gaussianOf(c, regularized));
  });
}

}  // namespace ndtom
