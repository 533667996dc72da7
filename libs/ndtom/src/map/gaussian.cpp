#include "ndtom/map/gaussian.h"

#include "ndtom/map/eigenvalue_floor.h"

namespace ndtom {

Eigen::Matrix3d regularizedCovariance(const Eigen::Matrix3d& covariance,
                                      const Regularization& reg) {
  return floorEigenvalues(covariance, reg.min_eigen_abs, reg.min_eigen_ratio).matrix();
}

}  // namespace ndtom
