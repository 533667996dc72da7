#include "loop_picture.h"

#include <algorithm>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>

#include "ndtom_apps/top_view.h"

namespace ndtom::slam {
namespace {

apps::ColouredPath pathOf(const SlamResult& r, bool optimized) {
  const LoopClosureReport& loops = *r.loops;
  const std::vector<Eigen::Isometry3d>& anchors =
      optimized ? loops.anchors_optimized : loops.anchors_odometry;
  apps::ColouredPath p;
  for (const SlamScan& s : r.scans)
    p.points.push_back((optimized ? s.step.pose : s.odometry).translation());
  if (!optimized) p.colours.assign(p.points.size(), cv::Scalar(40, 40, 220));  // red (BGR)
  for (const LoopRecord& l : loops.loops)
    if (l.check.accepted)
      p.links.emplace_back(anchors[l.older].translation(), anchors[l.newer].translation());
  p.legend = std::string(optimized ? "black: after the pose graph's optimization"
                                   : "red: odometry, before optimization") +
             " (from o); magenta: the " + std::to_string(loops.accepted) +
             " loop closures between keyframes";
  return p;
}

cv::Mat padToHeight(const cv::Mat& image, int rows) {
  cv::Mat out;
  cv::copyMakeBorder(image, out, 0, rows - image.rows, 0, 0, cv::BORDER_CONSTANT,
                     cv::Scalar(255, 255, 255));
  return out;
}

}  // namespace

cv::Mat loopClosurePicture(const ndtom::NdtMap& map, const apps::HeightScale& scale,
                           const SlamResult& result, int width) {
  if (!result.loops) throw std::logic_error("loopClosurePicture: a run without loop closure");
  const cv::Mat before = apps::renderTopView(map, scale, pathOf(result, false), width);
  const cv::Mat after = apps::renderTopView(map, scale, pathOf(result, true), width);
  const int rows = std::max(before.rows, after.rows);
  cv::Mat both;
  cv::hconcat(padToHeight(before, rows), padToHeight(after, rows), both);
  return both;
}

}  // namespace ndtom::slam
