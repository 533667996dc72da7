// The Fig. 4 renderer (apps/ndtom-eval/oblique_render.h): the ellipse it draws for a Gaussian
// has the shape of the 1-σ ellipsoid's surface points projected by hand, and nearer items
// cover farther ones whatever the order they were added in.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "oblique_render.h"

namespace {

namespace fs = std::filesystem;
using ndtom::Gaussian;
using ndtom::eval::ObliqueRender;

constexpr double kAzimuth = -60, kElevation = 40;
constexpr int kBottomRows = 45;  // the scale bar and its label

// Camera axes for the azimuth and elevation, written out by hand.
void axes(Eigen::Vector3d& right, Eigen::Vector3d& up, Eigen::Vector3d& towards_camera) {
  const double az = kAzimuth * M_PI / 180, el = kElevation * M_PI / 180;
  right = {-std::sin(az), std::cos(az), 0};
  up = {-std::sin(el) * std::cos(az), -std::sin(el) * std::sin(az), std::cos(el)};
  towards_camera = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
}

fs::path tempPng(const std::string& name) {
  return fs::temp_directory_path() / (name + std::to_string(getpid()) + ".png");
}

TEST(ObliqueRender, EllipseHasTheShapeOfTheProjectedEllipsoid) {
  Gaussian g;
  g.mean = {1, 2, 0.5};
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  g.covariance = r * Eigen::Vector3d(9.0, 2.25, 0.04).asDiagonal() * r.transpose();
  const std::vector<Eigen::Vector3d> extent = {g.mean - Eigen::Vector3d::Constant(10),
                                               g.mean + Eigen::Vector3d::Constant(10)};
  ObliqueRender render(extent, kAzimuth, kElevation, 1200);
  render.addGaussian(g, {0, 0, 255});
  const fs::path file = tempPng("oblique_shape_");
  render.write(file.string(), "", {});
  const cv::Mat image = cv::imread(file.string());
  fs::remove(file);
  ASSERT_FALSE(image.empty());
  int x0 = image.cols, x1 = -1, y0 = image.rows, y1 = -1;
  double n = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;  // moments of the ellipse's pixels
  for (int y = 40; y < image.rows - kBottomRows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
      if (p[2] > 100 && p[0] < 100) {  // red-ish: the ellipse (fill or anti-aliased edge)
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        n += 1, sx += x, sy += y, sxx += double(x) * x, syy += double(y) * y, sxy += double(x) * y;
      }
    }
  ASSERT_GT(x1, x0);
  // The 1-σ surface x = mean + L s (|s| = 1), sampled and projected onto the image axes.
  Eigen::Vector3d right, up, towards;
  axes(right, up, towards);
  const Eigen::Matrix3d l = g.covariance.llt().matrixL();
  double u0 = 1e9, u1 = -1e9, v0 = 1e9, v1 = -1e9;
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j <= 100; ++j) {
      const double phi = 2 * M_PI * i / 200, theta = M_PI * j / 100;
      const Eigen::Vector3d s(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                              std::cos(theta));
      const Eigen::Vector3d x = g.mean + l * s;
      u0 = std::min(u0, x.dot(right)), u1 = std::max(u1, x.dot(right));
      v0 = std::min(v0, x.dot(up)), v1 = std::max(v1, x.dot(up));
    }
  // The 1-pixel outline and anti-aliasing may add up to kSlack pixels to each side's extent.
  constexpr double kSlack = 3;
  const double width_px = x1 - x0 + 1, height_px = y1 - y0 + 1;
  ASSERT_GT(height_px, 60);  // large enough for the slack to be small
  const double ratio = (u1 - u0) / (v1 - v0);
  EXPECT_NEAR(width_px / height_px, ratio, ratio * (kSlack / width_px + kSlack / height_px));
  // Orientation: a filled ellipse's pixels correlate like the projected covariance
  // C = [right up]^T P [right up] (image rows grow downwards: the sign of v flips). The
  // bounding box alone would not see a mirrored ellipse.
  const double cxx = sxx / n - (sx / n) * (sx / n), cyy = syy / n - (sy / n) * (sy / n);
  const double cxy = sxy / n - (sx / n) * (sy / n);
  const double c_uu = right.dot(g.covariance * right), c_vv = up.dot(g.covariance * up);
  const double c_uv = right.dot(g.covariance * up);
  ASSERT_GT(std::abs(c_uv) / std::sqrt(c_uu * c_vv), 0.2);  // a clearly tilted ellipse
  EXPECT_NEAR(cxy / std::sqrt(cxx * cyy), -c_uv / std::sqrt(c_uu * c_vv), 0.03);
  // The same scale on both axes (a parallel projection keeps lengths in the image plane).
  const double pixels_per_metre = width_px / (u1 - u0);
  EXPECT_NEAR(height_px / (v1 - v0), pixels_per_metre,
              pixels_per_metre * (kSlack / width_px + kSlack / height_px));
}

TEST(ObliqueRender, NearerItemsCoverFartherOnesInAnyOrder) {
  Eigen::Vector3d right, up, towards;
  axes(right, up, towards);
  for (bool near_first : {true, false}) {
    Gaussian far, near;
    far.covariance = near.covariance = Eigen::Matrix3d::Identity() * 0.25;
    far.mean = {0, 0, 0};
    near.mean = far.mean + 5 * towards;  // same image position, nearer the camera
    ObliqueRender render({far.mean - Eigen::Vector3d::Constant(6),
                          far.mean + Eigen::Vector3d::Constant(6), near.mean},
                         kAzimuth, kElevation, 600);
    if (near_first) render.addGaussian(near, {255, 0, 0});  // blue
    render.addGaussian(far, {0, 0, 255});                   // red
    if (!near_first) render.addGaussian(near, {255, 0, 0});
    const fs::path file = tempPng("oblique_order_");
    render.write(file.string(), "", {});
    const cv::Mat image = cv::imread(file.string());
    fs::remove(file);
    ASSERT_FALSE(image.empty());
    // Every pixel of the shared disc's interior is blue, none red.
    size_t blue = 0, red = 0;
    for (int y = 40; y < image.rows - kBottomRows; ++y)
      for (int x = 0; x < image.cols; ++x) {
        const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
        blue += p[0] > 200 && p[2] < 50;
        red += p[2] > 200 && p[0] < 50;
      }
    EXPECT_GT(blue, 100u) << "near first: " << near_first;
    EXPECT_EQ(red, 0u) << "near first: " << near_first;
  }
}

}  // namespace
