#include "ndtom_eval/trajectory_error.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ndtom {

TrajectoryError alignedTrajectoryError(const std::vector<Eigen::Vector3d>& estimate,
                                       const std::vector<Eigen::Vector3d>& reference) {
  if (estimate.size() != reference.size())
    throw std::invalid_argument("trajectory error: " + std::to_string(estimate.size()) +
                                " estimated poses for " + std::to_string(reference.size()) +
                                " reference poses");
  if (estimate.size() < 3)
    throw std::invalid_argument("trajectory error: needs at least 3 poses");
  const Eigen::Index n = Eigen::Index(estimate.size());
  Eigen::Matrix3Xd from(3, n), to(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    from.col(i) = estimate[size_t(i)];
    to.col(i) = reference[size_t(i)];
  }
  TrajectoryError out;
  out.poses = estimate.size();
  out.alignment.matrix() = Eigen::umeyama(from, to, /*with_scaling=*/false);
  double squared = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double e = (out.alignment * estimate[size_t(i)] - reference[size_t(i)]).norm();
    squared += e * e;
    out.max = std::max(out.max, e);
    out.final = e;
    if (i > 0) out.length += (reference[size_t(i)] - reference[size_t(i) - 1]).norm();
  }
  out.rmse = std::sqrt(squared / double(n));
  return out;
}

}  // namespace ndtom
