// The registration's local pose parameters δ = (v, ω): a translation and a rotation vector
// in the map frame, the rotation turning about the sensor, so pose ⊕ δ = (Exp(ω)·R, t + v).
// Turning about the sensor rather than the map's origin keeps rotation and translation
// apart for maps far from their origin.
#pragma once

#include <Eigen/Geometry>

#include "ndtom/registration/registration.h"

namespace ndtom::registration {

inline Eigen::Isometry3d applyIncrement(const Eigen::Isometry3d& pose, const Vector6d& delta) {
  const Eigen::Vector3d omega = delta.tail<3>();
  const double angle = omega.norm();
  Eigen::Isometry3d out = pose;
  if (angle > 0)
    out.linear() = Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix() * pose.linear();
  out.translation() += delta.head<3>();
  return out;
}

/// [v]×: the matrix of v × (·).
inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

}  // namespace ndtom::registration
