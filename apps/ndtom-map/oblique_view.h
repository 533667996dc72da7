// The map in 3D from an oblique camera: the occupied Gaussians as shaded 1-σ ellipsoids
// (the plugin's batched mesh), rendered off-screen by MRPT's CFBORender, which brings its own
// EGL context (Mesa's software renderer does without a display or a GPU).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "height_colors.h"
#include "mrpt_ndtom/ndt_visualization.h"
#include "ndtom/ndt_map.h"

namespace ndtom::mapper {

/// What both the picture and the .3Dscene draw: the map's Gaussians coloured on `scale`.
mrpt_ndtom::TRenderOptions renderOptionsFor(const HeightScale& scale, uint32_t max_ellipsoids);

/// The framed picture (caption, colour bar), at most `width` pixels wide and 0.7 times as
/// high, cropped to the drawing. Throws if no off-screen OpenGL context can be created.
cv::Mat renderObliqueView(const ndtom::NdtMap& map, const mrpt_ndtom::TRenderOptions& options,
                          const std::vector<Eigen::Vector3d>& sensor_path, int width);

}  // namespace ndtom::mapper
