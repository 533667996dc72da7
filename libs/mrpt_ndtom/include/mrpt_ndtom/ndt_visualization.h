// Drawing an NDT-OM: each occupied Gaussian as a shaded ellipsoid (k-σ surface, coloured by
// height), all of them batched into one triangle mesh so that tens of thousands draw fast;
// free cells optionally as points. Used by CNDTOccupancyMap::getVisualizationInto() and by
// programs that render maps offscreen.
#pragma once

#include <mrpt/opengl/CSetOfObjects.h>

#include <cstdint>
#include <vector>

#include "mrpt_ndtom/render_options.h"
#include "ndtom/map/ndt_map.h"

namespace mrpt_ndtom {

/// Triangles drawn per ellipsoid at `subdivisions` (see TRenderOptions): 8·4^subdivisions.
size_t trianglesPerEllipsoid(uint32_t subdivisions);

/// The ellipsoids of one scene hold at most this many triangles (~100 bytes each in the mesh,
/// as much again in a viewer): past it the tessellation is coarsened, down to octahedra, and
/// then only the best-supported kMaxSceneTriangles / 8 Gaussians are drawn.
inline constexpr size_t kMaxSceneTriangles = size_t(1) << 20;
/// The subdivisions `drawn` ellipsoids get: `requested`, or fewer within kMaxSceneTriangles.
uint32_t subdivisionsWithinBudget(size_t drawn, uint32_t requested);

/// An occupied Gaussian as drawn: regularised (so that its ellipsoid has volume) and coloured
/// by the height of its mean.
struct DrawnGaussian {
  ndtom::Gaussian gaussian;
  mrpt::img::TColor color;
};

/// The Gaussians that `options` draw: those of occupied cells above `min_logodds`, the
/// best-supported `max_ellipsoids` (at most kMaxSceneTriangles / 8) of them, in cell order. Throws
/// on invalid options.
std::vector<DrawnGaussian> drawnGaussians(const ndtom::NdtMap& map, const TRenderOptions& options);

/// Appends to `out` a CSetOfTriangles named "ndtom_gaussians" (if any Gaussian qualifies)
/// and, if enabled, a CPointCloudColoured named "ndtom_free_cells".
void buildNdtVisualization(const ndtom::NdtMap& map, const TRenderOptions& options,
                           mrpt::opengl::CSetOfObjects& out);
/// The same for Gaussians already selected with drawnGaussians(map, options).
void buildNdtVisualization(const ndtom::NdtMap& map, const std::vector<DrawnGaussian>& drawn,
                           const TRenderOptions& options, mrpt::opengl::CSetOfObjects& out);

}  // namespace mrpt_ndtom
