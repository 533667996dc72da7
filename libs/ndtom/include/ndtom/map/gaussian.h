// The Gaussian of a cell as handed to users (queries, drawing, likelihood, registration).
// Regularisation happens here, on a copy: the cell's statistics stay exact.
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "ndtom/map/cell_index.h"

namespace ndtom {

struct Gaussian {
  CellIndex cell;
  uint32_t n = 0;                                        ///< points behind the estimate
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();        ///< world frame (m)
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  ///< unbiased sample covariance (m²)
};

/// Eigenvalue floor for the covariance used by queries: thin (planar) cells are otherwise
/// singular. Each eigenvalue is raised to max(min_eigen_ratio · λ_max, min_eigen_abs).
struct Regularization {
  double min_eigen_ratio = 0.01;  ///< (Default: 0.01, condition number ≤ 100)
  double min_eigen_abs = 1e-6;    ///< (Default: 1e-6 m², i.e. σ ≥ 1 mm)
};

/// Symmetric covariance with its eigenvalues floored as `reg` says.
Eigen::Matrix3d regularizedCovariance(const Eigen::Matrix3d& covariance, const Regularization& reg);

}  // namespace ndtom
