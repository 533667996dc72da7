#include "ndtom_apps/top_view.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "ndtom/map/map_queries.h"
#include "ndtom_apps/picture_layout.h"
#include "ndtom_apps/top_canvas.h"

namespace ndtom::apps {
namespace {

const cv::Scalar kUnknown(222, 222, 222), kFree(255, 255, 255), kThinOccupied(185, 185, 185);
constexpr double kTileTint = 0.45;  // occupied columns: this much of the height colour on white
constexpr int kMargin = 16;         // px around the map

struct Frame : apps::TopFrame {
  int width = 0, height = 0;  ///< of the view (px)
};

double quantile(std::vector<double>& v, double q) {
  const size_t k = std::min(v.size() - 1, size_t(q * double(v.size())));
  std::nth_element(v.begin(), v.begin() + long(k), v.end());
  return v[k];
}

// The extent of the occupied Gaussians (without the farthest 0.2% on each side: stray
// points) and of the sensor path, plus 4% on each side. Free space beyond is cut off.
Frame frameFor(const ndtom::NdtMap& map, const std::vector<Eigen::Vector3d>& path, int view_width) {
  std::vector<double> xs, ys;
  map.forEachCell([&](const ndtom::CellView& c) {
    if (!ndtom::isOccupiedGaussian(map, c)) return;
    const Eigen::Vector3d p = map.geometry().cellCenter(c.index);
    xs.push_back(p.x());
    ys.push_back(p.y());
  });
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  if (!xs.empty()) {
    x_min = quantile(xs, 0.002), x_max = quantile(xs, 0.998);
    y_min = quantile(ys, 0.002), y_max = quantile(ys, 0.998);
  }
  for (const auto& p : path) {
    x_min = std::min(x_min, p.x()), x_max = std::max(x_max, p.x());
    y_min = std::min(y_min, p.y()), y_max = std::max(y_max, p.y());
  }
  const double r = map.options().resolution;
  const double pad_x = 0.04 * (x_max - x_min) + r, pad_y = 0.04 * (y_max - y_min) + r;
  Frame f;
  f.margin = kMargin;
  f.x_min = x_min - pad_x;
  f.y_max = y_max + pad_y;
  const double dx = x_max - x_min + 2 * pad_x, dy = y_max - y_min + 2 * pad_y;
  const int inner = view_width - 2 * kMargin;
  f.pixels_per_metre = std::min(inner / dx, 1.2 * inner / dy);
  // A tall map gets a narrower picture rather than empty margins.
  f.width = std::max(int(std::ceil(dx * f.pixels_per_metre)) + 2 * kMargin, 360);
  f.height = std::max(int(std::ceil(dy * f.pixels_per_metre)) + 2 * kMargin, 360);
  return f;
}

// The ground under the ellipses, column by column: a pale tint of the height colour of the
// highest occupied Gaussian, grey for occupied cells with too few points for a Gaussian,
// white for free space, darker grey where nothing is known. Occupied beats free beats unknown.
void drawColumns(const ndtom::NdtMap& map, const Frame& f, const HeightScale& scale,
                 cv::Mat& view) {
  cv::Mat state(view.size(), CV_8U, cv::Scalar(0));
  cv::Mat top_z(view.size(), CV_32F, cv::Scalar(-std::numeric_limits<float>::infinity()));
  map.forEachCell([&](const ndtom::CellView& c) {
    const ndtom::CellState cell_state = ndtom::cellState(map, c);
    if (cell_state == ndtom::CellState::Unknown) return;
    const uint8_t s = cell_state == ndtom::CellState::Free ? 1 : 2;
    const float z = ndtom::isOccupiedGaussian(map, c) ? float(map.gaussianOf(c).mean.z())
                                                      : -std::numeric_limits<float>::infinity();
    const Eigen::Vector3d p = map.geometry().cellCenter(c.index);
    const cv::Rect r = f.squarePixels(p.x(), p.y(), map.options().resolution, view.size());
    for (int y = r.y; y < r.y + r.height; ++y)
      for (int x = r.x; x < r.x + r.width; ++x) {
        state.at<uint8_t>(y, x) = std::max(state.at<uint8_t>(y, x), s);
        top_z.at<float>(y, x) = std::max(top_z.at<float>(y, x), z);
      }
  });
  const cv::Scalar white(255, 255, 255);
  view.forEach<cv::Vec3b>([&](cv::Vec3b& pixel, const int* at) {
    const uint8_t s = state.at<uint8_t>(at[0], at[1]);
    const float z = top_z.at<float>(at[0], at[1]);
    cv::Scalar color = s == 0 ? kUnknown : (s == 1 ? kFree : kThinOccupied);
    if (std::isfinite(z)) color = kTileTint * scale.bgr(z) + (1 - kTileTint) * white;
    pixel = cv::Vec3b(uchar(color[0]), uchar(color[1]), uchar(color[2]));
  });
}

// Returns how many were drawn.
size_t drawGaussians(const ndtom::NdtMap& map, const Frame& f, const HeightScale& scale,
                     cv::Mat& view) {
  std::vector<ndtom::Gaussian> gaussians;
  map.forEachCell([&](const ndtom::CellView& c) {
    if (ndtom::isOccupiedGaussian(map, c)) gaussians.push_back(map.gaussianOf(c));
  });
  apps::fillXyEllipsesByHeight(view, f, gaussians, [&](double z) { return scale.bgr(z); });
  return gaussians.size();
}

// The path, each segment in the colour of its end (black if none given), its start as `o`.
void drawPath(const std::vector<Eigen::Vector3d>& path, const std::vector<cv::Scalar>& colours,
              const Frame& f, cv::Mat& view) {
  if (path.empty()) return;
  const std::vector<cv::Point> pixels = f.toPixels(path);
  const cv::Scalar black(0, 0, 0);
  if (colours.empty()) {
    cv::polylines(view, pixels, false, black, 2, cv::LINE_AA);
  } else {
    for (size_t i = 0; i < pixels.size(); ++i) {
      const cv::Point& from = pixels[i == 0 ? 0 : i - 1];
      cv::line(view, from, pixels[i], colours[i], 3, cv::LINE_AA);
      cv::circle(view, pixels[i], 3, colours[i], cv::FILLED, cv::LINE_AA);
    }
  }
  cv::circle(view, pixels.front(), 6, black, cv::FILLED, cv::LINE_AA);
  cv::circle(view, pixels.front(), 3, cv::Scalar(255, 255, 255), cv::FILLED, cv::LINE_AA);
}

void drawLinks(const ColouredPath& path, const Frame& f, cv::Mat& view) {
  for (const auto& [a, b] : path.links) {
    const cv::Point2d pa = f.toPixel(a.x(), a.y()), pb = f.toPixel(b.x(), b.y());
    cv::line(view, pa, pb, path.link_colour, 2, cv::LINE_AA);
    cv::circle(view, pa, 4, path.link_colour, cv::FILLED, cv::LINE_AA);
    cv::circle(view, pb, 4, path.link_colour, cv::FILLED, cv::LINE_AA);
  }
}

}  // namespace

cv::Mat renderTopView(const ndtom::NdtMap& map, const HeightScale& scale,
                      const std::vector<Eigen::Vector3d>& sensor_path, int width) {
  ColouredPath path;
  path.points = sensor_path;
  path.legend = "black: sensor path from o";
  return renderTopView(map, scale, path, width);
}

cv::Mat renderTopView(const ndtom::NdtMap& map, const HeightScale& scale, const ColouredPath& path,
                      int width) {
  std::vector<Eigen::Vector3d> extent = path.points;
  extent.insert(extent.end(), path.reference.begin(), path.reference.end());
  const Frame f = frameFor(map, extent, viewWidth(width));
  cv::Mat view(f.height, f.width, CV_8UC3);
  drawColumns(map, f, scale, view);
  const size_t drawn = drawGaussians(map, f, scale, view);
  if (!path.reference.empty())
    cv::polylines(view, f.toPixels(path.reference), false, cv::Scalar(110, 110, 110), 1,
                  cv::LINE_AA);
  drawPath(path.points, path.colours, f, view);
  drawLinks(path, f, view);
  apps::drawScaleBar(view, f.pixels_per_metre);
  char title[160];
  std::snprintf(title, sizeof title, "NDT-OM, top view: %zu occupied Gaussians, %g m cells", drawn,
                map.options().resolution);
  return composePicture(view, title,
                        "1-sigma ellipses by height, on the colour of the highest one in their "
                        "column; white: free; grey: unknown; " +
                            path.legend,
                        scale);
}

}  // namespace ndtom::apps
