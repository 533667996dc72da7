#include "ndtom/gaussian.h"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace ndtom {

Eigen::Matrix3d regularizedCovariance(const Eigen::Matrix3d& covariance,
                                      const Regularization& reg) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(covariance);
  Eigen::Vector3d lambda = eig.eigenvalues();  // ascending
  const double floor_value = std::max(reg.min_eigen_ratio * lambda[2], reg.min_eigen_abs);
  for (int i = 0; i < 3; ++i) lambda[i] = std::max(lambda[i], floor_value);
  const Eigen::Matrix3d& v = eig.eigenvectors();
  return v * lambda.asDiagonal() * v.transpose();
}

}  // namespace ndtom
