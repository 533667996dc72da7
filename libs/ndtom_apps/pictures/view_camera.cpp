#include "ndtom_apps/view_camera.h"

#include <Eigen/Geometry>
#include <cmath>

namespace ndtom::apps {

ViewCamera ViewCamera::orbiting(const Eigen::Vector3d& target, double distance,
                                double azimuth_deg, double elevation_deg, double fov_deg,
                                cv::Size size) {
  const double az = azimuth_deg * M_PI / 180, el = elevation_deg * M_PI / 180;
  const Eigen::Vector3d towards_eye(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                    std::sin(el));
  ViewCamera c;
  c.eye = target + distance * towards_eye;
  c.forward = -towards_eye;
  // Looking straight down leaves no horizon: +y is then up in the picture.
  const Eigen::Vector3d side = c.forward.cross(Eigen::Vector3d::UnitZ());
  c.right = side.norm() > 1e-9 ? side.normalized() : Eigen::Vector3d::UnitX();
  c.up = c.right.cross(c.forward);
  c.focal_px = 0.5 * size.height / std::tan(0.5 * fov_deg * M_PI / 180);
  c.size = size;
  return c;
}

}  // namespace ndtom::apps
