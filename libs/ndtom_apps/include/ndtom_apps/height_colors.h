// Colours by height, shared by the pictures and the 3D scene so that one legend fits all:
// MRPT's jet colour map over a height range taken from the occupied Gaussians.
#pragma once

#include <opencv2/core.hpp>

#include "ndtom/map/ndt_map.h"

namespace ndtom::apps {

struct HeightScale {
  double z_min = 0, z_max = 1;  ///< (m) blue at z_min, red at z_max, clamped beyond

  /// Position of `z` on the scale, in [0, 1].
  double fraction(double z) const;
  /// The colour of `z` for OpenCV (blue, green, red).
  cv::Scalar bgr(double z) const;
};

/// The 2nd to 98th percentile of the means of the Gaussians in occupied cells (as the
/// plugin's drawing picks it), so a few stray points do not wash out the colours.
/// A map without such Gaussians gets [0, 1].
HeightScale heightScaleOf(const ndtom::NdtMap& map);

}  // namespace ndtom::apps
