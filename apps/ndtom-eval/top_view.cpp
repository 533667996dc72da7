#include "top_view.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "ndtom_apps/top_canvas.h"

namespace ndtom::eval {

cv::Scalar viridis(double t) {
  static const cv::Mat lut = [] {
    cv::Mat grey(1, 256, CV_8UC1), colored;
    for (int i = 0; i < 256; ++i) grey.at<uint8_t>(0, i) = uint8_t(i);
    cv::applyColorMap(grey, colored, cv::COLORMAP_VIRIDIS);
    return colored;
  }();
  const int i = std::clamp(int(std::lround(t * 255.0)), 0, 255);
  const cv::Vec3b c = lut.at<cv::Vec3b>(0, i);
  return {double(c[0]), double(c[1]), double(c[2])};
}

TopView::TopView(const std::vector<Eigen::Vector3d>& extent, double margin, int max_pixels) {
  if (extent.empty()) throw std::invalid_argument("TopView: nothing to show");
  Eigen::Vector2d lo = extent[0].head<2>(), hi = lo;
  for (const Eigen::Vector3d& p : extent) {
    lo = lo.cwiseMin(p.head<2>());
    hi = hi.cwiseMax(p.head<2>());
  }
  lo.array() -= margin;
  hi.array() += margin;
  metres_per_pixel_ = std::max(hi.x() - lo.x(), hi.y() - lo.y()) / max_pixels;
  frame_.x_min = lo.x();
  frame_.y_max = hi.y();
  frame_.pixels_per_metre = 1 / metres_per_pixel_;
  const int cols = int(std::ceil((hi.x() - lo.x()) / metres_per_pixel_));
  const int rows = int(std::ceil((hi.y() - lo.y()) / metres_per_pixel_));
  image_ = cv::Mat(rows, cols, CV_8UC3, cv::Scalar::all(255));
}

void TopView::drawGaussians(const std::vector<Gaussian>& gaussians, const cv::Scalar& color) {
  for (const Gaussian& g : gaussians)
    apps::fillXyEllipse(image_, frame_, g.mean, g.covariance, color);
}

void TopView::drawGaussiansByHeight(std::vector<Gaussian> gaussians, double z_min, double z_max) {
  apps::fillXyEllipsesByHeight(image_, frame_, std::move(gaussians),
                               [&](double z) { return viridis((z - z_min) / (z_max - z_min)); });
}

void TopView::drawCells(const std::vector<CellIndex>& cells, double resolution,
                        const cv::Scalar& color) {
  for (const CellIndex& c : cells)
    cv::rectangle(image_,
                  frame_.squarePixels((c.x + 0.5) * resolution, (c.y + 0.5) * resolution,
                                      resolution, image_.size()),
                  color, cv::FILLED);
}

void TopView::drawPath(const std::vector<Eigen::Vector3d>& path, const cv::Scalar& color) {
  cv::polylines(image_, frame_.toPixels(path), false, color, 3, cv::LINE_AA);
}

void TopView::drawLegend(const std::vector<std::pair<std::string, cv::Scalar>>& entries) {
  int y = 25;
  for (const auto& [text, color] : entries) {
    cv::rectangle(image_, {12, y - 12}, {28, y + 4}, color, cv::FILLED);
    cv::putText(image_, text, {36, y + 2}, kLabelFont, 0.6, kLabelInk, 1, cv::LINE_AA);
    y += 26;
  }
  apps::drawScaleBar(image_, frame_.pixels_per_metre);
}

void TopView::drawHeightBar(double z_min, double z_max) {
  const int x = image_.cols - 30, top = 40, bottom = std::min(image_.rows - 40, 340);
  for (int y = top; y <= bottom; ++y)
    cv::line(image_, {x, y}, {x + 18, y}, viridis(double(bottom - y) / (bottom - top)));
  char label[32];
  std::snprintf(label, sizeof(label), "z %.1f m", z_max);
  cv::putText(image_, label, {x - 95, top + 5}, kLabelFont, 0.5, kLabelInk, 1, cv::LINE_AA);
  std::snprintf(label, sizeof(label), "z %.1f m", z_min);
  cv::putText(image_, label, {x - 95, bottom + 5}, kLabelFont, 0.5, kLabelInk, 1, cv::LINE_AA);
}

void TopView::write(const std::string& path) const {
  if (!cv::imwrite(path, image_, {cv::IMWRITE_PNG_COMPRESSION, 9}))
    throw std::runtime_error("cannot write " + path);
}

}  // namespace ndtom::eval
