// What the programs' top views (looking down the z axis) share: world xy to pixels to scale,
// the 1-σ ellipses of Gaussians drawn from low to high, cell squares, paths, and the scale
// bar. Each program composes its own picture from these.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <opencv2/core.hpp>
#include <vector>

namespace ndtom::apps {

/// Metres to pixels: x to the right, y up; (x_min, y_max) lands `margin` px in from the
/// top-left corner.
struct TopFrame {
  double x_min = 0, y_max = 0, pixels_per_metre = 1;
  int margin = 0;

  cv::Point2d toPixel(double x, double y) const {
    return {margin + (x - x_min) * pixels_per_metre, margin + (y_max - y) * pixels_per_metre};
  }
  /// Each point's pixel, rounded.
  std::vector<cv::Point> toPixels(const std::vector<Eigen::Vector3d>& points) const;
  /// The pixels of the square of edge `edge` (m) centred at (x, y), clipped to `size`; at
  /// least one pixel, so that cells smaller than a pixel still show.
  cv::Rect squarePixels(double x, double y, double edge, const cv::Size& size) const;
};

/// Fills the 1-σ ellipse of the xy marginal of a Gaussian (world frame), each semi-axis at
/// least 0.7 px so that thin ones stay visible, placed to 1/16 px.
void fillXyEllipse(cv::Mat& image, const TopFrame& frame, const Eigen::Vector3d& mean,
                   const Eigen::Matrix3d& covariance, const cv::Scalar& color);

/// Fills the ellipses of `gaussians` (anything with `mean` and `covariance`) in the colour
/// `color_of(z)` of their mean's height, from low to high so that the top of every column
/// shows.
template <class G, class ColorOf>
void fillXyEllipsesByHeight(cv::Mat& image, const TopFrame& frame, std::vector<G> gaussians,
                            const ColorOf& color_of) {
  std::sort(gaussians.begin(), gaussians.end(),
            [](const G& a, const G& b) { return a.mean.z() < b.mean.z(); });
  for (const G& g : gaussians)
    fillXyEllipse(image, frame, g.mean, g.covariance, color_of(g.mean.z()));
}

/// A bar of a round length (1, 2 or 5 times a power of ten metres, about a fifth of the
/// width) on a pale box in the lower left corner; none if it would not fit.
void drawScaleBar(cv::Mat& image, double pixels_per_metre);

}  // namespace ndtom::apps
