// The eigenvalue floor of a covariance, computed here only: queries regularise the covariance
// handed to users with it (Regularization), the likelihood's lookup keeps its inverses finite,
// and the evaluation's similarity keeps its determinants positive.
#pragma once

#include <Eigen/Core>

namespace ndtom {

/// A symmetric 3×3 matrix as its eigenvectors and ascending eigenvalues, each eigenvalue
/// raised to at least max(min_ratio · λ_max, min_abs) (min_abs alone for min_ratio = 0).
struct FlooredEigen {
  Eigen::Vector3d values;   ///< ascending, floored
  Eigen::Matrix3d vectors;  ///< one per column
  bool raised = false;      ///< whether an eigenvalue was below the floor

  /// The floored matrix, V · diag(values) · Vᵀ.
  Eigen::Matrix3d matrix() const { return vectors * values.asDiagonal() * vectors.transpose(); }
};

FlooredEigen floorEigenvalues(const Eigen::Matrix3d& symmetric, double min_abs,
                              double min_ratio = 0.0);

}  // namespace ndtom
