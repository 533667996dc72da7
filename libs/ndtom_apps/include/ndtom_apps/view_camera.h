// A pinhole camera looking at a point from an azimuth and an elevation, z up (the way MRPT's
// viewers orbit a scene), for pictures drawn without OpenGL.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace ndtom::apps {

struct ViewCamera {
  Eigen::Vector3d eye, forward, right, up;  ///< position and unit axes (right × up = -forward)
  double focal_px = 1;                      ///< pixels per unit of tan(angle)
  cv::Size size;                            ///< image size, px

  /// Looking at `target` from `distance` away, at `azimuth_deg` (from +x towards +y) and
  /// `elevation_deg` (above the x-y plane), with a vertical field of view `fov_deg`.
  static ViewCamera orbiting(const Eigen::Vector3d& target, double distance, double azimuth_deg,
                             double elevation_deg, double fov_deg, cv::Size size);

  /// The ray through pixel (x, y) (pixel centres at +0.5): its direction has unit forward
  /// component, so the ray's parameter is the depth along the view axis.
  Eigen::Vector3d rayThrough(double x, double y) const {
    return forward + (x - 0.5 * size.width) / focal_px * right +
           (0.5 * size.height - y) / focal_px * up;
  }

  /// Where `p` falls in the image and its depth along the view axis (≤ 0: behind the eye).
  Eigen::Vector3d project(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d q = p - eye;
    const double depth = q.dot(forward);
    return {0.5 * size.width + focal_px * q.dot(right) / depth,
            0.5 * size.height - focal_px * q.dot(up) / depth, depth};
  }
};

}  // namespace ndtom::apps
