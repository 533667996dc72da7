// The picture of a run with loop closure: the map from above, the trajectory before the
// pose graph's optimization (odometry) on the left and after it on the right, the accepted
// loop closures as lines between their keyframes.
#pragma once

#include <opencv2/core.hpp>

#include "ndtom_apps/height_colors.h"
#include "slam_loop.h"

namespace ndtom::slam {

/// Two top views side by side, `width` pixels each. Needs result.loops.
cv::Mat loopClosurePicture(const ndtom::NdtMap& map, const apps::HeightScale& scale,
                           const SlamResult& result, int width);

}  // namespace ndtom::slam
