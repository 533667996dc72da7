#include "ndtom/map/eigenvalue_floor.h"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace ndtom {

FlooredEigen floorEigenvalues(const Eigen::Matrix3d& symmetric, double min_abs, double min_ratio) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(symmetric);
  FlooredEigen f;
  f.values = eig.eigenvalues();
  f.vectors = eig.eigenvectors();
  const double floor_value = min_ratio > 0 ? std::max(min_ratio * f.values[2], min_abs) : min_abs;
  for (int i = 0; i < 3; ++i)
    if (f.values[i] < floor_value) {
      f.values[i] = floor_value;
      f.raised = true;
    }
  return f;
}

}  // namespace ndtom
