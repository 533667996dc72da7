#include "ndtom_apps/oblique_view.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "ndtom/map/map_queries.h"
#include "ndtom_apps/depth_canvas.h"
#include "ndtom_apps/picture_layout.h"

namespace ndtom::apps {
namespace {

constexpr double kAzimuthDeg = -75, kElevationDeg = 40, kFieldOfViewDeg = 30;
// Rendered twice as large, then shrunk (smooth edges), while the canvas (colour and depth,
// 7 bytes a pixel) stays within this: --image-width 8000 took 1.5 GB supersampled.
constexpr double kMaxSupersampledPixels = 40e6;
const cv::Vec3b kBackground(255, 255, 255);
constexpr int kMinViewWidth = 480;  // px: room for the caption

struct Box {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Ones();
};

// Where the occupied Gaussians are, without the 1% farthest on each side of each axis.
Box robustBox(const ndtom::NdtMap& map) {
  std::vector<double> axis[3];
  map.forEachCell([&](const ndtom::CellView& c) {
    if (!ndtom::isOccupiedGaussian(map, c)) return;
    const Eigen::Vector3d m = map.gaussianOf(c).mean;
    for (int k = 0; k < 3; ++k) axis[k].push_back(m[k]);
  });
  Box box;
  if (axis[0].empty()) return box;
  for (int k = 0; k < 3; ++k) {
    auto& v = axis[k];
    const size_t lo = v.size() / 100, hi = v.size() - 1 - v.size() / 100;
    std::nth_element(v.begin(), v.begin() + long(lo), v.end());
    box.lo[k] = v[lo];
    std::nth_element(v.begin(), v.begin() + long(hi), v.end());
    box.hi[k] = v[hi];
  }
  return box;
}

// [first, last] of the indices holding all but `trim` of `counts`' total at each end.
std::pair<int, int> trimmedRange(const cv::Mat& counts, double trim) {
  const double total = cv::sum(counts)[0], cut = trim * total;
  int first = 0, last = int(counts.total()) - 1;
  for (double seen = 0; first < last && seen + counts.at<float>(first) <= cut; ++first)
    seen += counts.at<float>(first);
  for (double seen = 0; last > first && seen + counts.at<float>(last) <= cut; --last)
    seen += counts.at<float>(last);
  return {first, last};
}

// The rendered image cropped to what differs from the background, plus a margin; a few
// stray specks (1% of the drawn pixels at each side) do not widen the picture.
cv::Mat cropToContent(const cv::Mat& image) {
  cv::Mat mask;
  cv::inRange(image, kBackground, kBackground, mask);
  cv::bitwise_not(mask, mask);
  if (cv::countNonZero(mask) == 0) return image;
  cv::Mat drawn, columns, rows;
  mask.convertTo(drawn, CV_32F, 1.0 / 255);
  cv::reduce(drawn, columns, 0, cv::REDUCE_SUM);
  cv::reduce(drawn, rows, 1, cv::REDUCE_SUM);
  const auto [x0, x1] = trimmedRange(columns, 0.01);
  const auto [y0, y1] = trimmedRange(rows, 0.01);
  const int margin = image.cols / 40;
  const cv::Rect padded(x0 - margin, y0 - margin, x1 - x0 + 1 + 2 * margin,
                        y1 - y0 + 1 + 2 * margin);
  return image(padded & cv::Rect(0, 0, image.cols, image.rows));
}

// `image` scaled to fit in `size`; narrower content gives a narrower result (no empty
// margins), though never below `min_width`, where it is centred.
cv::Mat fitInto(const cv::Mat& image, cv::Size size, int min_width) {
  const double s = std::min(double(size.width) / image.cols, double(size.height) / image.rows);
  cv::Mat scaled;
  cv::resize(image, scaled, cv::Size(), s, s, s < 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
  if (scaled.cols >= min_width) return scaled;
  cv::Mat out(scaled.rows, min_width, CV_8UC3, cv::Scalar(kBackground));
  scaled.copyTo(out(cv::Rect((min_width - scaled.cols) / 2, 0, scaled.cols, scaled.rows)));
  return out;
}

cv::Mat renderGaussians(const std::vector<mrpt_ndtom::DrawnGaussian>& drawn, double quantiles,
                        const std::vector<Eigen::Vector3d>& sensor_path, const Box& box,
                        cv::Size size, int view_width) {
  const Eigen::Vector3d centre = (box.lo + box.hi) / 2;
  const double radius = std::max(0.5 * (box.hi - box.lo).norm(), 0.5);
  const double distance = 1.05 * radius / std::sin(kFieldOfViewDeg / 2 * M_PI / 180);
  DepthCanvas canvas(
      ViewCamera::orbiting(centre, distance, kAzimuthDeg, kElevationDeg, kFieldOfViewDeg, size),
      kBackground);
  const double k2 = quantiles * quantiles;
  for (const auto& d : drawn)
    canvas.drawEllipsoid(d.gaussian.mean, k2 * d.gaussian.covariance,
                         cv::Vec3b(d.color.B, d.color.G, d.color.R));
  canvas.drawPolyline(sensor_path, cv::Vec3b(0, 0, 0), 2 * size.width / view_width);
  return canvas.image();
}

}  // namespace

mrpt_ndtom::TRenderOptions renderOptionsFor(const ndtom::NdtMap& map, const HeightScale& scale,
                                            uint32_t max_ellipsoids, int detail) {
  mrpt_ndtom::TRenderOptions o;
  o.color_min_z = scale.z_min;
  o.color_max_z = scale.z_max;
  o.max_ellipsoids = max_ellipsoids;
  const size_t drawn = std::min<size_t>(map.numGaussians(), max_ellipsoids);
  o.subdivisions = detail >= 0      ? mrpt_ndtom::subdivisionsWithinBudget(drawn, uint32_t(detail))
                   : drawn <= 8000  ? 2
                   : drawn <= 20000 ? 1
                                    : 0;
  return o;
}

cv::Mat renderObliqueView(const ndtom::NdtMap& map,
                          const std::vector<mrpt_ndtom::DrawnGaussian>& drawn,
                          const mrpt_ndtom::TRenderOptions& o,
                          const std::vector<Eigen::Vector3d>& sensor_path, int width) {
  const cv::Size view(viewWidth(width), int(0.7 * viewWidth(width)));
  const cv::Mat rendered =
      renderGaussians(drawn, o.quantiles, sensor_path, robustBox(map),
                      view * (4.0 * view.area() <= kMaxSupersampledPixels ? 2 : 1), view.width);
  const HeightScale scale{o.color_min_z, o.color_max_z};
  char title[160];
  std::snprintf(title, sizeof title, "NDT-OM, 3D view: %zu Gaussians, %g m cells",
                map.numGaussians(), map.options().resolution);
  return composePicture(fitInto(cropToContent(rendered), view, kMinViewWidth), title,
                        "shaded 1-sigma ellipsoids of the occupied cells, coloured by height; "
                        "black: sensor path",
                        scale);
}

}  // namespace ndtom::apps
