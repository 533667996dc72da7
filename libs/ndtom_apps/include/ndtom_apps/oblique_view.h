// The map in 3D from an oblique camera: the occupied Gaussians as shaded k-σ ellipsoids (the
// ones the plugin draws, in its colours), ray-cast exactly on the CPU. No OpenGL context:
// Mesa's renderer alone took more memory than the whole mapping.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "mrpt_ndtom/ndt_visualization.h"
#include "ndtom/map/ndt_map.h"
#include "ndtom_apps/height_colors.h"

namespace ndtom::apps {

/// What both the picture and the .3Dscene draw: the map's Gaussians coloured on `scale`.
/// `detail` (the scene's subdivisions) -1 picks by how many are drawn: 128 triangles each up
/// to 8000, 32 up to 20000, else 8 (octahedra): each triangle takes ~100 bytes in the mesh,
/// and the scene's viewer holds as much again. A `detail` that would pass
/// mrpt_ndtom::kMaxSceneTriangles is lowered until it does not.
mrpt_ndtom::TRenderOptions renderOptionsFor(const ndtom::NdtMap& map, const HeightScale& scale,
                                            uint32_t max_ellipsoids, int detail = -1);

/// The framed picture (caption, colour bar), at most `width` pixels wide and 0.7 times as
/// high, cropped to the drawing, of `drawn` (drawnGaussians() of `map` with `options`:
/// selected once for the scene and the picture) and the sensor path.
cv::Mat renderObliqueView(const ndtom::NdtMap& map,
                          const std::vector<mrpt_ndtom::DrawnGaussian>& drawn,
                          const mrpt_ndtom::TRenderOptions& options,
                          const std::vector<Eigen::Vector3d>& sensor_path, int width);

}  // namespace ndtom::apps
