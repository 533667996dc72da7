// The Gaussians of a map prepared for queries that run many times per scan (likelihood,
// registration): regularised covariance inverted once, found by cell in O(1) and by nearest
// mean through a k-d tree. An immutable snapshot: build it again after the map changes.
//
// Threading: every member is const after construction, so concurrent queries are safe.
#pragma once

#include <Eigen/Core>
#include <unordered_map>
#include <vector>

#include "ndtom/cell_index.h"
#include "ndtom/ndt_map.h"
#include "ndtom/point_kdtree.h"

namespace ndtom {

struct PreparedGaussian {
  CellIndex cell;
  uint32_t n = 0;                                  ///< points behind the estimate
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();  ///< world frame (m)
  /// Inverse of the regularised covariance (m⁻²): d² = (p − μ)ᵀ·this·(p − μ).
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  /// λ_min·Σ⁻¹ of the regularised covariance (dimensionless): applied to p − μ it keeps the
  /// offset along the Gaussian's thinnest axis whole and shrinks the others by λ_min/λ_i, so
  /// p − projection·(p − μ) is p moved onto a planar cell's plane, a linear cell's line, or
  /// a round cell's mean.
  Eigen::Matrix3d projection = Eigen::Matrix3d::Zero();
};

class GaussianLookup {
 public:
  /// Every cell of `map` with a Gaussian (N ≥ 3), its covariance regularised as the map's
  /// options say. O(G log G) for G Gaussians.
  explicit GaussianLookup(const NdtMap& map);

  const GridGeometry& geometry() const { return geometry_; }
  size_t size() const { return gaussians_.size(); }
  bool empty() const { return gaussians_.empty(); }
  /// In ascending cell order: deterministic whatever the map's insertion history.
  const std::vector<PreparedGaussian>& gaussians() const { return gaussians_; }

  /// The Gaussian of a cell; nullptr if the cell has none.
  const PreparedGaussian* find(const CellIndex& cell) const;
  /// The Gaussian of the cell holding `point`; nullptr if none or the point is out of range.
  const PreparedGaussian* findAt(const Eigen::Vector3d& point) const;

  /// k-d tree over the means; its indices are those of gaussians().
  const PointKdTree& means() const { return means_; }

 private:
  GridGeometry geometry_;
  std::vector<PreparedGaussian> gaussians_;
  std::unordered_map<CellIndex, uint32_t, CellIndexHash> by_cell_;
  PointKdTree means_;
};

/// Squared Mahalanobis distance of `point` to `g` (its regularised covariance).
inline double squaredMahalanobis(const PreparedGaussian& g, const Eigen::Vector3d& point) {
  const Eigen::Vector3d d = point - g.mean;
  return d.dot(g.information * d);
}

}  // namespace ndtom
