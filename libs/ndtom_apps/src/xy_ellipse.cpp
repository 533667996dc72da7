#include "ndtom_apps/xy_ellipse.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace ndtom::apps {

XyEllipse xyEllipse(const Eigen::Matrix3d& covariance) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(covariance.topLeftCorner<2, 2>());
  const Eigen::Vector2d sigma = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();  // ascending
  const Eigen::Vector2d major = eig.eigenvectors().col(1);
  // Image y points down: the angle flips sign.
  return {sigma[1], sigma[0], -std::atan2(major.y(), major.x()) * 180.0 / M_PI};
}

}  // namespace ndtom::apps
