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
/// `detail` (subdivisions) -1 picks by how many are drawn: 128 triangles each up to 8000,
/// 32 up to 20000, else 8 (octahedra). Each triangle takes ~100 bytes in the mesh and as much
/// again in the renderer: 46,000 ellipsoids at 32 triangles took 166 + 367 MB.
mrpt_ndtom::TRenderOptions renderOptionsFor(const ndtom::NdtMap& map, const HeightScale& scale,
                                            uint32_t max_ellipsoids, int detail = -1);

/// The framed picture (caption, colour bar), at most `width` pixels wide and 0.7 times as
/// high, cropped to the drawing, of `gaussians` (buildNdtVisualization() of `map` with
/// `options`: built once for the scene and the picture). Throws if no off-screen OpenGL
/// context can be created.
cv::Mat renderObliqueView(const ndtom::NdtMap& map, const mrpt::opengl::CSetOfObjects::Ptr& gaussians,
                          const mrpt_ndtom::TRenderOptions& options,
                          const std::vector<Eigen::Vector3d>& sensor_path, int width);

}  // namespace ndtom::mapper
