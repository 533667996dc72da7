// Headless 3D pictures for Fig. 4 with OpenCV only: a parallel (orthographic) projection seen
// from above at an angle, painter's order (far to near). Under a parallel projection the
// outline of a Gaussian's 1-σ ellipsoid is exactly the 1-σ ellipse of its projected
// covariance, so each Gaussian is one filled ellipse; cells are drawn as small spheres (discs).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "ndtom/map/gaussian.h"

namespace ndtom::eval {

class ObliqueRender {
 public:
  /// Frames the points `extent` (with a margin) in a `width`-pixel-wide picture, seen from
  /// azimuth `azimuth_deg` (direction the camera sits in, from +x towards +y) and
  /// `elevation_deg` above the horizon.
  ObliqueRender(const std::vector<Eigen::Vector3d>& extent, double azimuth_deg,
                double elevation_deg, int width = 1600);

  /// Queue a Gaussian's 1-σ ellipsoid (outline a darker shade of `colour`).
  void addGaussian(const Gaussian& g, const cv::Scalar& colour);
  /// Queue a sphere of `radius` m at `centre`.
  void addSphere(const Eigen::Vector3d& centre, double radius, const cv::Scalar& fill,
                 const cv::Scalar& outline);
  /// Queue the sensor path (drawn on top of everything).
  void setPath(const std::vector<Eigen::Vector3d>& path, const cv::Scalar& colour);

  /// Draws the queue far to near, then the title, the legend and a scale bar; throws
  /// std::runtime_error if the file cannot be written.
  void write(const std::string& path, const std::string& title,
             const std::vector<std::pair<std::string, cv::Scalar>>& legend,
             const std::pair<double, double>* height_bar = nullptr) const;

 private:
  struct Item {
    double depth;        ///< along the viewing direction; larger is nearer the camera
    cv::Point2d centre;  ///< pixels
    cv::Size2d axes;     ///< pixels (semi-axes)
    double angle;        ///< degrees, image convention
    cv::Scalar fill, outline;
  };
  cv::Point2d project(const Eigen::Vector3d& p) const;

  Eigen::Vector3d right_, up_, towards_camera_;
  double u_min_ = 0, v_max_ = 0, pixels_per_metre_ = 1;
  int width_ = 0, height_ = 0;
  std::vector<Item> items_;
  std::vector<cv::Point> path_;
  cv::Scalar path_colour_;
};

}  // namespace ndtom::eval
