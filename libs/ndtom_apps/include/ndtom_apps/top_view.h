// The map seen from above, drawn to scale with OpenCV: free space white, unknown grey, the
// occupied Gaussians as their 1-σ ellipses in the horizontal plane, coloured by height and
// drawn from low to high so that the top of every column shows; the sensor path on top.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "ndtom/map/ndt_map.h"
#include "ndtom_apps/height_colors.h"

namespace ndtom::apps {

/// The framed picture (caption, colour bar, scale bar), at most `width` pixels wide and
/// 1.2 times as high; narrower for maps longer in y than in x.
cv::Mat renderTopView(const ndtom::NdtMap& map, const HeightScale& scale,
                      const std::vector<Eigen::Vector3d>& sensor_path, int width);

/// A path drawn in colours of its own, e.g. by localization error.
struct ColouredPath {
  std::vector<Eigen::Vector3d> points;
  std::vector<cv::Scalar> colours;         ///< of the segment ending at each point (BGR)
  std::vector<Eigen::Vector3d> reference;  ///< drawn thin and grey beneath, if any
  std::string legend;                      ///< what the colours mean, for the caption
  /// Pairs of points joined by straight lines on top (loop closures between keyframes).
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> links;
  cv::Scalar link_colour{255, 0, 255};
};
cv::Mat renderTopView(const ndtom::NdtMap& map, const HeightScale& scale, const ColouredPath& path,
                      int width);

}  // namespace ndtom::apps
