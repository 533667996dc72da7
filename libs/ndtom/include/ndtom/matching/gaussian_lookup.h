// The Gaussians of a map prepared for queries that run many times per scan (likelihood,
// registration): regularised covariance inverted once, found by cell in O(1) and by nearest
// mean through a k-d tree. A snapshot of the map: build it again after the map changes, or
// update() the cells that changed.
//
// Threading: const members are safe to call concurrently; update() is not.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <optional>
#include <vector>

#include "ndtom/map/block_grid.h"
#include "ndtom/map/cell_index.h"
#include "ndtom/map/gaussian.h"
#include "ndtom/map/ndt_map.h"
#include "ndtom/matching/point_kdtree.h"

namespace ndtom {

/// A Gaussian whose covariance is regularised, with what the queries derive from it.
struct PreparedGaussian : Gaussian {
  /// The covariance's inverse (m⁻²): d² = (p − μ)ᵀ·information·(p − μ).
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  double max_variance = 0;  ///< its largest eigenvalue (m²): d² ≥ |p − μ|² / max_variance
  /// λ_min·Σ⁻¹ of the regularised covariance (dimensionless): applied to p − μ it keeps the
  /// offset along the Gaussian's thinnest axis whole and shrinks the others by λ_min/λ_i, so
  /// p − projection·(p − μ) is p moved onto a planar cell's plane, a linear cell's line, or
  /// a round cell's mean.
  Eigen::Matrix3d projection = Eigen::Matrix3d::Zero();
};

struct LookupOptions {
  /// Only cells believed occupied (log-odds > 0) when the map tracks occupancy: free space
  /// and vanished objects attract nothing (Default: false, every Gaussian).
  bool occupied_only = false;
  /// Build the k-d tree behind means() (Default: true).
  bool nearest_means = true;
};

/// The Gaussian `g` (covariance regularised already) prepared for queries: its covariance's
/// eigenvalues floored at 1e-12 m² so it always has an inverse.
PreparedGaussian prepared(const Gaussian& g);
/// The same for a Gaussian with its exact covariance, regularised as `reg` says on the way:
/// one eigen decomposition, not two (the pyramid makes one per coarse cell it redoes).
PreparedGaussian prepared(const Gaussian& exact, const Regularization& reg);

/// A cell's new Gaussian, or none (the cell loses it), for GaussianLookup::update().
struct CellChange {
  CellIndex cell;
  std::optional<PreparedGaussian> gaussian;
};

/// One block's Gaussians, for GaussianLookup's constructor from blocks made elsewhere.
struct GaussianBlock {
  CellIndex block;
  std::array<uint64_t, kBlockCells / 64> cells{};  ///< a bit per Gaussian at offsetInBlock()
  std::vector<PreparedGaussian> gaussians;         ///< in offset order
};

class GaussianLookup {
 public:
  /// Every cell of `map` with a Gaussian (N ≥ 3), its covariance regularised as the map's
  /// options say. O(G log G) for G Gaussians.
  explicit GaussianLookup(const NdtMap& map, const LookupOptions& options = {});
  /// The given Gaussians (their covariance regularised already, one per cell) on the grid of
  /// `geometry`: levels made without a map of their own (MapPyramid's coarse levels).
  /// `options.occupied_only` is the caller's to have applied.
  GaussianLookup(const GridGeometry& geometry, const std::vector<Gaussian>& gaussians,
                 const LookupOptions& options = {});
  /// The same from Gaussians prepared already (prepared()), in any order.
  GaussianLookup(const GridGeometry& geometry, std::vector<PreparedGaussian> gaussians,
                 const LookupOptions& options = {});
  /// From blocks made elsewhere, e.g. on several threads (MapPyramid): in ascending block
  /// order, each block's Gaussians in offset order and inside it; empty blocks are skipped.
  /// O(blocks + Gaussians) and the Gaussians are not read again; throws
  /// std::invalid_argument for blocks out of order or bits that do not count the Gaussians.
  GaussianLookup(const GridGeometry& geometry, std::vector<GaussianBlock> blocks,
                 const LookupOptions& options = {});
  // Moved, not copied: the k-d tree's owners point into the blocks.
  GaussianLookup(GaussianLookup&&) noexcept = default;
  GaussianLookup& operator=(GaussianLookup&&) noexcept = default;
  GaussianLookup(const GaussianLookup&) = delete;
  GaussianLookup& operator=(const GaussianLookup&) = delete;

  const GridGeometry& geometry() const { return geometry_; }
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  /// f(const PreparedGaussian&) for each Gaussian, block by block in ascending block order
  /// and by offset in a block (offsetInBlock()): deterministic whatever the map's history.
  template <class F>
  void forEachGaussian(F&& f) const;
  /// Heap bytes of the Gaussians and their index (not the k-d tree).
  size_t memoryBytes() const;
  /// Most bytes one Gaussian can add to memoryBytes() (one block of its own), for budgets.
  static size_t maxBytesPerGaussian();

  /// Sets or clears the Gaussians of the given cells (one change per cell), so that a level
  /// follows a map that changed in a few places (MapPyramid) instead of being built again.
  /// O(changes + the Gaussians of the blocks they touch). Throws std::logic_error for a
  /// lookup with a k-d tree (LookupOptions::nearest_means), which would go stale.
  void update(std::vector<CellChange> changes);

  /// The Gaussian of a cell; nullptr if the cell has none.
  const PreparedGaussian* find(const CellIndex& cell) const;
  /// The Gaussian of the cell holding `point`; nullptr if none or the point is out of range.
  const PreparedGaussian* findAt(const Eigen::Vector3d& point) const;
  /// f(const PreparedGaussian&) for each Gaussian in the 3×3×3 cells centred on `centre`
  /// (in no particular order). One block lookup per block touched, usually one or two.
  template <class F>
  void forEachAround(const CellIndex& centre, F&& f) const;

  /// k-d tree over the means, in forEachGaussian()'s order; meanOwner(i) is the Gaussian of
  /// its i-th point. Empty unless built (LookupOptions::nearest_means).
  const PointKdTree& means() const { return means_; }
  const PreparedGaussian& meanOwner(uint32_t i) const { return *mean_owners_[i]; }

 private:
  /// Inline: without -mpopcnt (Debian's x86-64 baseline) the builtin is a call into libgcc.
  static uint32_t popcount(uint64_t x) {
#ifdef __POPCNT__
    return uint32_t(__builtin_popcountll(x));
#else
    x = x - ((x >> 1) & 0x5555555555555555ULL);
    x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
    x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0FULL;
    return uint32_t((x * 0x0101010101010101ULL) >> 56);
#endif
  }
  /// One block's Gaussians, in offset order, found by the rank of their cell's bit: a
  /// block's Gaussians sit together (the 27 neighbours of a point usually share one block),
  /// and a block can be rewritten alone when the map changes there.
  struct IndexBlock {
    static constexpr size_t kWords = kBlockCells / 64;
    std::array<uint64_t, kWords> occupied{};
    std::array<uint16_t, kWords> before{};  ///< cells with a Gaussian in the earlier words
    std::vector<PreparedGaussian> gaussians;
    const PreparedGaussian* gaussianAt(uint32_t offset) const {
      const uint64_t word = occupied[offset >> 6], bit = uint64_t(1) << (offset & 63);
      if (!(word & bit)) return nullptr;
      return &gaussians[before[offset >> 6] + popcount(word & (bit - 1))];
    }
    /// `occupied` and `before` from the cells of `gaussians`.
    void reindex();
    /// `before` from `occupied`.
    void countBefore();
  };
  /// Fills the blocks from Gaussians in any order and builds the k-d tree if asked.
  void index(std::vector<PreparedGaussian> gaussians, bool nearest_means);
  void indexMeans(bool nearest_means);
  std::vector<std::pair<CellIndex, const IndexBlock*>> blocksInOrder() const;

  GridGeometry geometry_;
  size_t size_ = 0;
  BlockGrid<IndexBlock> by_cell_;  // blocks, not a hash per cell: neighbours share a block
  bool nearest_means_ = false;
  PointKdTree means_;
  std::vector<const PreparedGaussian*> mean_owners_;
};

template <class F>
void GaussianLookup::forEachGaussian(F&& f) const {
  for (const auto& [key, block] : blocksInOrder())
    for (const PreparedGaussian& g : block->gaussians) f(g);
}

template <class F>
void GaussianLookup::forEachAround(const CellIndex& centre, F&& f) const {
  const CellIndex lo{centre.x - 1, centre.y - 1, centre.z - 1};
  const CellIndex hi{centre.x + 1, centre.y + 1, centre.z + 1};
  const CellIndex block_lo = blockOf(lo), block_hi = blockOf(hi);
  for (int32_t bz = block_lo.z; bz <= block_hi.z; ++bz)
    for (int32_t by = block_lo.y; by <= block_hi.y; ++by)
      for (int32_t bx = block_lo.x; bx <= block_hi.x; ++bx) {
        const IndexBlock* block = by_cell_.find({bx, by, bz});
        if (!block) continue;
        // The part of the neighbourhood inside this block.
        const CellIndex first = cellInBlock({bx, by, bz}, 0);
        const int32_t x0 = std::max(lo.x, first.x), x1 = std::min(hi.x, first.x + kBlockEdge - 1);
        const int32_t y0 = std::max(lo.y, first.y), y1 = std::min(hi.y, first.y + kBlockEdge - 1);
        const int32_t z0 = std::max(lo.z, first.z), z1 = std::min(hi.z, first.z + kBlockEdge - 1);
        for (int32_t z = z0; z <= z1; ++z)
          for (int32_t y = y0; y <= y1; ++y)
            for (int32_t x = x0; x <= x1; ++x)
              if (const PreparedGaussian* g = block->gaussianAt(offsetInBlock({x, y, z}))) f(*g);
      }
}

/// Squared Mahalanobis distance of `point` to `g` (its regularised covariance).
inline double squaredMahalanobis(const PreparedGaussian& g, const Eigen::Vector3d& point) {
  const Eigen::Vector3d d = point - g.mean;
  return d.dot(g.information * d);
}

}  // namespace ndtom
