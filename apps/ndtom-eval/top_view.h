// Top views (looking down the z axis) of maps, drawn on the programs' top canvas
// (ndtom_apps/top_canvas.h): Gaussians as their 1-σ ellipses in the xy plane, cells as
// filled squares, the sensor path as a line.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <utility>
#include <vector>

#include "ndtom/map/cell_index.h"
#include "ndtom/map/gaussian.h"
#include "ndtom_apps/top_canvas.h"

namespace ndtom::eval {

/// The figures' labels: font and ink.
inline constexpr int kLabelFont = cv::FONT_HERSHEY_SIMPLEX;
inline const cv::Scalar kLabelInk{20, 20, 20};

class TopView {
 public:
  /// Covers the xy bounding box of `extent` plus `margin` (m), the longer side `max_pixels`.
  TopView(const std::vector<Eigen::Vector3d>& extent, double margin = 2.0, int max_pixels = 1600);

  double metresPerPixel() const { return metres_per_pixel_; }

  /// Filled 1-σ ellipses of the xy marginals, coloured by height (viridis over
  /// [z_min, z_max]); drawn from low to high so that the view shows the top surface.
  void drawGaussiansByHeight(std::vector<Gaussian> gaussians, double z_min, double z_max);
  /// Filled 1-σ ellipses in one colour.
  void drawGaussians(const std::vector<Gaussian>& gaussians, const cv::Scalar& color);
  /// Filled squares of the cells' xy footprint.
  void drawCells(const std::vector<CellIndex>& cells, double resolution, const cv::Scalar& color);
  void drawPath(const std::vector<Eigen::Vector3d>& path, const cv::Scalar& color);
  /// Text lines with colour swatches at the top left, and a scale bar.
  void drawLegend(const std::vector<std::pair<std::string, cv::Scalar>>& entries);
  /// A colour bar for drawGaussiansByHeight.
  void drawHeightBar(double z_min, double z_max);

  /// Throws std::runtime_error if the file cannot be written.
  void write(const std::string& path) const;

 private:
  apps::TopFrame frame_;
  double metres_per_pixel_;
  cv::Mat image_;
};

/// Viridis colour (BGR) of t in [0, 1].
cv::Scalar viridis(double t);

}  // namespace ndtom::eval
