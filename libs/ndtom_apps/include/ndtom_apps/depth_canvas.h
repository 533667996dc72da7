// A picture drawn surface by surface with a depth buffer, without OpenGL: what is nearer the
// camera hides what is behind. Ellipsoids are ray-cast exactly per pixel (a quadratic per
// pixel in the ellipsoid's screen box), so thousands of Gaussians draw in a fraction of a
// second with no mesh and no graphics driver in memory.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "ndtom_apps/view_camera.h"

namespace ndtom::apps {

class DepthCanvas {
 public:
  DepthCanvas(const ViewCamera& camera, const cv::Vec3b& background);

  /// The surface (x − centre)ᵀ shape⁻¹ (x − centre) = 1 (shape symmetric positive definite),
  /// lit from above the camera. Skipped if the eye is inside it or behind the image plane.
  void drawEllipsoid(const Eigen::Vector3d& centre, const Eigen::Matrix3d& shape,
                     const cv::Vec3b& bgr);
  /// A polyline `width_px` wide, hidden where a surface drawn before is in front of it.
  void drawPolyline(const std::vector<Eigen::Vector3d>& points, const cv::Vec3b& bgr,
                    int width_px);

  const cv::Mat3b& image() const { return image_; }
  /// Depth along the view axis of what each pixel shows (+inf: background).
  const cv::Mat1f& depth() const { return depth_; }

 private:
  ViewCamera camera_;
  Eigen::Vector3d light_;  ///< unit, towards the light
  cv::Mat3b image_;
  cv::Mat1f depth_;
};

}  // namespace ndtom::apps
