#include "ndtom_apps/top_canvas.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>

#include "ndtom_apps/round_step.h"
#include "ndtom_apps/xy_ellipse.h"

namespace ndtom::apps {

namespace {
constexpr int kSubpixelBits = 4;
const cv::Scalar kInk(40, 40, 40), kPaper(255, 255, 255);
}  // namespace

std::vector<cv::Point> TopFrame::toPixels(const std::vector<Eigen::Vector3d>& points) const {
  std::vector<cv::Point> pixels;
  pixels.reserve(points.size());
  for (const auto& p : points) {
    const cv::Point2d q = toPixel(p.x(), p.y());
    pixels.emplace_back(int(std::lround(q.x)), int(std::lround(q.y)));
  }
  return pixels;
}

cv::Rect TopFrame::squarePixels(double x, double y, double edge, const cv::Size& size) const {
  const double half = edge / 2;
  const cv::Point2d a = toPixel(x - half, y + half);
  const cv::Point2d b = toPixel(x + half, y - half);
  const int x0 = int(std::floor(a.x)), y0 = int(std::floor(a.y));
  const int x1 = std::max(x0 + 1, int(std::floor(b.x))),
            y1 = std::max(y0 + 1, int(std::floor(b.y)));
  return cv::Rect(x0, y0, x1 - x0, y1 - y0) & cv::Rect(0, 0, size.width, size.height);
}

void fillXyEllipse(cv::Mat& image, const TopFrame& frame, const Eigen::Vector3d& mean,
                   const Eigen::Matrix3d& covariance, const cv::Scalar& color) {
  const double unit = 1 << kSubpixelBits;
  const XyEllipse e = xyEllipse(covariance);
  const double major = std::max(e.sigma_major * frame.pixels_per_metre, 0.7),
               minor = std::max(e.sigma_minor * frame.pixels_per_metre, 0.7);
  const cv::Point2d c = frame.toPixel(mean.x(), mean.y());
  cv::ellipse(image, cv::Point(int(c.x * unit), int(c.y * unit)),
              cv::Size(int(major * unit), int(minor * unit)), e.image_angle, 0, 360, color,
              cv::FILLED, cv::LINE_AA, kSubpixelBits);
}

void drawScaleBar(cv::Mat& image, double pixels_per_metre) {
  if (!(pixels_per_metre > 0)) return;
  const double length = roundStep(0.2 * image.cols / pixels_per_metre, 1);
  const int bar = int(std::lround(length * pixels_per_metre));
  const cv::Point start(20, image.rows - 20);
  if (bar < 10 || bar > image.cols - 40) return;
  cv::Mat box = image(cv::Rect(10, image.rows - 50, bar + 20, 42));
  const cv::Mat paper(box.size(), box.type(), kPaper);
  cv::addWeighted(box, 0.35, paper, 0.65, 0.0, box);  // readable on any map
  cv::line(image, start, start + cv::Point(bar, 0), kInk, 3);
  cv::line(image, start + cv::Point(0, -6), start + cv::Point(0, 6), kInk, 2);
  cv::line(image, start + cv::Point(bar, -6), start + cv::Point(bar, 6), kInk, 2);
  cv::putText(image, stepLabel(length, length) + " m", start + cv::Point(0, -12),
              cv::FONT_HERSHEY_SIMPLEX, 0.5, kInk, 1, cv::LINE_AA);
}

}  // namespace ndtom::apps
