// The top views' canvas: the frame's pixels, cell squares, ellipses and the scale bar, against
// positions and sizes worked out by hand.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "ndtom_apps/top_canvas.h"

using ndtom::apps::TopFrame;

namespace {

// Columns (or rows) of `image` holding a pixel of exactly `color`: first and last.
std::pair<int, int> span(const cv::Mat& image, const cv::Scalar& color, bool columns) {
  int first = -1, last = -1;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
      if (p[0] != color[0] || p[1] != color[1] || p[2] != color[2]) continue;
      const int k = columns ? x : y;
      first = first < 0 ? k : std::min(first, k);
      last = std::max(last, k);
    }
  return {first, last};
}

}  // namespace

TEST(TopCanvas, FrameMapsXRightAndYUpFromTheMargin) {
  TopFrame f;
  f.x_min = -3, f.y_max = 7, f.pixels_per_metre = 20, f.margin = 16;
  const cv::Point2d a = f.toPixel(-3, 7);
  EXPECT_DOUBLE_EQ(a.x, 16);
  EXPECT_DOUBLE_EQ(a.y, 16);
  const cv::Point2d b = f.toPixel(-1, 4);  // 2 m right, 3 m down
  EXPECT_DOUBLE_EQ(b.x, 16 + 40);
  EXPECT_DOUBLE_EQ(b.y, 16 + 60);
  const std::vector<cv::Point> path = f.toPixels({{-2.99, 6.99, 5}, {-2.0, 7.0, 0}});
  EXPECT_EQ(path[0], cv::Point(16, 16));  // 0.2 px: rounded
  EXPECT_EQ(path[1], cv::Point(36, 16));
}

TEST(TopCanvas, SquareCoversTheCellAndSmallCellsStillOnePixel) {
  TopFrame f;
  f.pixels_per_metre = 10;  // x_min 0, y_max 0: the world's (0, 0) at the corner
  const cv::Rect r = f.squarePixels(2.0, -1.0, 0.5, {100, 100});
  EXPECT_EQ(r, cv::Rect(17, 7, 5, 5));  // x 1.75..2.25 m: pixels 17.5..22.5, floored
  const cv::Rect tiny = f.squarePixels(2.02, -1.02, 0.01, {100, 100});
  EXPECT_EQ(tiny.area(), 1);
  EXPECT_EQ(f.squarePixels(50, -1, 1, {100, 100}).area(), 0) << "outside: clipped away";
}

TEST(TopCanvas, EllipseSpansTwoSigmaAlongEachAxis) {
  TopFrame f;
  f.x_min = -10, f.y_max = 10, f.pixels_per_metre = 10;
  cv::Mat image(200, 200, CV_8UC3, cv::Scalar::all(255));
  const cv::Scalar red(0, 0, 255);
  // σx = 3 m, σy = 1 m, centred on the world origin: pixel (100, 100).
  ndtom::apps::fillXyEllipse(image, f, {0, 0, 0}, Eigen::Vector3d(9, 1, 4).asDiagonal(), red);
  const auto [x0, x1] = span(image, red, true);
  const auto [y0, y1] = span(image, red, false);
  EXPECT_NEAR(x0, 70, 2.0);
  EXPECT_NEAR(x1, 130, 2.0);
  EXPECT_NEAR(y0, 90, 2.0);
  EXPECT_NEAR(y1, 110, 2.0);
}

TEST(TopCanvas, HigherGaussiansAreDrawnOverLowerOnes) {
  struct G {
    Eigen::Vector3d mean;
    Eigen::Matrix3d covariance;
  };
  TopFrame f;
  f.x_min = -5, f.y_max = 5, f.pixels_per_metre = 10;
  cv::Mat image(100, 100, CV_8UC3, cv::Scalar::all(255));
  const Eigen::Matrix3d c = Eigen::Matrix3d::Identity();
  // Given high first: sorted, the low one (blue) lies beneath the high one (red).
  ndtom::apps::fillXyEllipsesByHeight(
      image, f, std::vector<G>{{{0, 0, 2}, c}, {{0, 0, 1}, c}},
      [](double z) { return z > 1.5 ? cv::Scalar(0, 0, 255) : cv::Scalar(255, 0, 0); });
  EXPECT_EQ(image.at<cv::Vec3b>(50, 50), cv::Vec3b(0, 0, 255));
}

TEST(TopCanvas, ScaleBarIsARoundFifthOfTheWidth) {
  cv::Mat image(300, 500, CV_8UC3, cv::Scalar::all(255));
  ndtom::apps::drawScaleBar(image, 10);  // 50 m wide: a fifth is 10 m, 100 px
  const int row = image.rows - 20;
  EXPECT_EQ(image.at<cv::Vec3b>(row, 20), cv::Vec3b(40, 40, 40));
  EXPECT_EQ(image.at<cv::Vec3b>(row, 120), cv::Vec3b(40, 40, 40));
  EXPECT_NE(image.at<cv::Vec3b>(row, 124), cv::Vec3b(40, 40, 40)) << "longer than 10 m";
  cv::Mat blank(300, 500, CV_8UC3, cv::Scalar::all(255));
  ndtom::apps::drawScaleBar(blank, 1000);  // a bar of 0.1 m = 100 px
  EXPECT_EQ(blank.at<cv::Vec3b>(row, 120), cv::Vec3b(40, 40, 40));
}
