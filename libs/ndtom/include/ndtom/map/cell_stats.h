// Sufficient statistics of the points in one cell: count N, mean μ and scatter
// S = Σ (x−μ)(x−μ)ᵀ, merged exactly by the Recursive Covariance Update (paper Eq. 2, 3, 11).
//
// The mean is stored relative to a reference point (the cell centre), so its precision does
// not depend on how far the cell is from the world origin (UTM-like coordinates keep ~1e-16
// relative precision). Raw sums of x and xxᵀ are never stored: their difference loses all
// precision far from the origin (Chan et al.).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace ndtom {

/// The paper computes a Gaussian only from 3 points on (Sec. IV-A-1).
inline constexpr uint32_t kMinPointsForGaussian = 3;
/// The point count saturates here rather than wrapping to a small number: a merge past 4.29e9
/// points keeps its exact weights in μ and scales S down with N, so S / (N − 1) is still
/// the covariance.
inline constexpr uint32_t kMaxCellPoints = UINT32_MAX;

struct CellStats {
  uint32_t n = 0;
  /// The mean relative to the cell's reference point (not the world frame).
  Eigen::Vector3d relative_mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();

  bool empty() const { return n == 0; }
  bool hasGaussian() const { return n >= kMinPointsForGaussian; }

  /// Unbiased sample covariance P = S / (N − 1) (Eq. 3). Requires n >= 2.
  Eigen::Matrix3d covariance() const { return scatter / double(n - 1); }

  /// RCU (Eq. 2, 11): this ← this ⊕ other. Both must share the same reference point.
  /// N saturates at kMaxCellPoints.
  void merge(const CellStats& other);

  /// Moves the mean into the box [-half, half]³ around the reference point. The mean of points
  /// in a cell lies in its closed box; rounding (of the point's cell far from the origin, of
  /// the sums) can leave it a few ulps outside, and the map keeps it inside.
  void clampMean(double half) { relative_mean = relative_mean.cwiseMax(-half).cwiseMin(half); }

  /// Two-pass batch statistics (Eq. 1) of points already expressed relative to the reference.
  static CellStats fromPoints(const std::vector<Eigen::Vector3d>& relative_points);

  /// The same statistics expressed relative to a reference point moved by `offset`
  /// (new_ref = old_ref + offset): only the mean changes.
  [[nodiscard]] CellStats shifted(const Eigen::Vector3d& offset) const {
    CellStats s = *this;
    s.relative_mean -= offset;
    return s;
  }
};

}  // namespace ndtom
