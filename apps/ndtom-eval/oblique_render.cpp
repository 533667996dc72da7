#include "oblique_render.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "top_view.h"

namespace ndtom::eval {

namespace {
constexpr int kTitleRows = 40;  // above the picture
}  // namespace

ObliqueRender::ObliqueRender(const std::vector<Eigen::Vector3d>& extent, double azimuth_deg,
                             double elevation_deg, int width)
    : width_(width) {
  if (extent.empty()) throw std::invalid_argument("ObliqueRender: nothing to show");
  const double az = azimuth_deg * M_PI / 180, el = elevation_deg * M_PI / 180;
  towards_camera_ = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
  right_ = {-std::sin(az), std::cos(az), 0};
  up_ = towards_camera_.cross(right_);
  double u_lo = 1e300, u_hi = -1e300, v_lo = 1e300, v_hi = -1e300;
  for (const Eigen::Vector3d& p : extent) {
    u_lo = std::min(u_lo, p.dot(right_)), u_hi = std::max(u_hi, p.dot(right_));
    v_lo = std::min(v_lo, p.dot(up_)), v_hi = std::max(v_hi, p.dot(up_));
  }
  const double margin = 0.03 * std::max(u_hi - u_lo, v_hi - v_lo) + 1.0;
  u_min_ = u_lo - margin;
  v_max_ = v_hi + margin;
  pixels_per_metre_ = width_ / (u_hi - u_lo + 2 * margin);
  height_ = int(std::ceil((v_hi - v_lo + 2 * margin) * pixels_per_metre_)) + kTitleRows;
}

cv::Point2d ObliqueRender::project(const Eigen::Vector3d& p) const {
  return {(p.dot(right_) - u_min_) * pixels_per_metre_,
          (v_max_ - p.dot(up_)) * pixels_per_metre_ + kTitleRows};
}

void ObliqueRender::addGaussian(const Gaussian& g, const cv::Scalar& colour) {
  Eigen::Matrix<double, 3, 2> basis;
  basis << right_, up_;
  const Eigen::Matrix2d c = basis.transpose() * g.covariance * basis;  // projected covariance
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(c);
  const Eigen::Vector2d major = eig.eigenvectors().col(1);  // in (right, up); image y is down
  const double angle = std::atan2(-major.y(), major.x()) * 180 / M_PI;
  const auto axis = [&](int i) {
    return std::max(0.5, std::sqrt(std::max(0.0, eig.eigenvalues()(i))) * pixels_per_metre_);
  };
  items_.push_back({g.mean.dot(towards_camera_),
                    project(g.mean),
                    {axis(1), axis(0)},
                    angle,
                    colour,
                    colour * 0.6});
}

void ObliqueRender::addSphere(const Eigen::Vector3d& centre, double radius, const cv::Scalar& fill,
                              const cv::Scalar& outline) {
  const double r = std::max(0.5, radius * pixels_per_metre_);
  items_.push_back({centre.dot(towards_camera_), project(centre), {r, r}, 0, fill, outline});
}

void ObliqueRender::setPath(const std::vector<Eigen::Vector3d>& path, const cv::Scalar& colour) {
  path_.clear();
  for (const Eigen::Vector3d& p : path) path_.emplace_back(project(p));
  path_colour_ = colour;
}

void ObliqueRender::write(const std::string& path, const std::string& title,
                          const std::vector<std::pair<std::string, cv::Scalar>>& legend,
                          const std::pair<double, double>* height_bar) const {
  cv::Mat image(height_, width_, CV_8UC3, cv::Scalar::all(255));
  std::vector<const Item*> order;
  for (const Item& item : items_) order.push_back(&item);
  std::stable_sort(order.begin(), order.end(),
                   [](const Item* a, const Item* b) { return a->depth < b->depth; });
  // Sub-pixel positions: cv::ellipse takes fixed-point coordinates with `shift` fraction bits.
  constexpr int kShift = 4;
  constexpr double kScale = 1 << kShift;
  for (const Item* item : order) {
    const cv::Point c(int(std::lround(item->centre.x * kScale)),
                      int(std::lround(item->centre.y * kScale)));
    const cv::Size axes(int(std::lround(item->axes.width * kScale)),
                        int(std::lround(item->axes.height * kScale)));
    cv::ellipse(image, c, axes, item->angle, 0, 360, item->fill, cv::FILLED, cv::LINE_AA, kShift);
    if (item->axes.width >= 2)
      cv::ellipse(image, c, axes, item->angle, 0, 360, item->outline, 1, cv::LINE_AA, kShift);
  }
  if (path_.size() > 1) cv::polylines(image, path_, false, path_colour_, 3, cv::LINE_AA);

  cv::rectangle(image, {0, 0}, {width_, kTitleRows - 6}, cv::Scalar::all(255), cv::FILLED);
  cv::putText(image, title, {12, 26}, kLabelFont, 0.7, kLabelInk, 1, cv::LINE_AA);
  int y = kTitleRows + 20;
  for (const auto& [text, colour] : legend) {
    cv::rectangle(image, {12, y - 12}, {28, y + 4}, colour, cv::FILLED);
    cv::rectangle(image, {12, y - 12}, {28, y + 4}, kLabelInk, 1);
    cv::putText(image, text, {36, y + 2}, kLabelFont, 0.55, kLabelInk, 1, cv::LINE_AA);
    y += 24;
  }
  if (height_bar) {
    const int x = width_ - 40, top = kTitleRows + 20, bottom = top + 240;
    for (int row = top; row <= bottom; ++row)
      cv::line(image, {x, row}, {x + 18, row}, viridis(double(bottom - row) / (bottom - top)));
    char label[32];
    std::snprintf(label, sizeof label, "z %.1f m", height_bar->second);
    cv::putText(image, label, {x - 95, top + 5}, kLabelFont, 0.5, kLabelInk, 1, cv::LINE_AA);
    std::snprintf(label, sizeof label, "z %.1f m", height_bar->first);
    cv::putText(image, label, {x - 95, bottom + 5}, kLabelFont, 0.5, kLabelInk, 1, cv::LINE_AA);
  }
  // Scale bar for horizontal distances across the picture (exact along the image's x axis).
  const double bar = width_ / pixels_per_metre_ > 60 ? 10 : 5;
  const int length = int(std::lround(bar * pixels_per_metre_)), by = height_ - 20;
  cv::line(image, {20, by}, {20 + length, by}, kLabelInk, 3);
  cv::putText(image, cv::format("%g m", bar), {28 + length, by + 5}, kLabelFont, 0.6, kLabelInk, 1,
              cv::LINE_AA);
  if (!cv::imwrite(path, image, {cv::IMWRITE_PNG_COMPRESSION, 9}))
    throw std::runtime_error("cannot write " + path);
}

}  // namespace ndtom::eval
