#include "localization/weak_directions.h"

#include <Eigen/Eigenvalues>

namespace ndtom::tracking {

int keepPredictionAlongWeakDirections(Eigen::Isometry3d& registered,
                                      const Eigen::Isometry3d& predicted,
                                      const Matrix6d& covariance, double max_sigma) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(covariance.topLeftCorner<3, 3>());
  const Eigen::Vector3d back = predicted.translation() - registered.translation();
  Eigen::Vector3d t = registered.translation();
  int weak = 0;
  for (int i = 0; i < 3; ++i) {
    if (!(eig.eigenvalues()[i] > max_sigma * max_sigma)) continue;
    const Eigen::Vector3d u = eig.eigenvectors().col(i);
    t += u * u.dot(back);
    ++weak;
  }
  registered.translation() = t;
  return weak;
}

}  // namespace ndtom::tracking
