// Drawing an NDT-OM: each occupied Gaussian as a shaded ellipsoid (k-σ surface, coloured by
// height), all of them batched into one triangle mesh so that tens of thousands draw fast;
// free cells optionally as points. Used by CNDTOccupancyMap::getVisualizationInto() and by
// programs that render maps offscreen.
#pragma once

#include <mrpt/opengl/CSetOfObjects.h>

#include <cstdint>

#include "mrpt_ndtom/render_options.h"
#include "ndtom/ndt_map.h"

namespace mrpt_ndtom {

/// Triangles drawn per ellipsoid at `subdivisions` (see TRenderOptions): 8·4^subdivisions.
size_t trianglesPerEllipsoid(uint32_t subdivisions);

/// Appends to `out` a CSetOfTriangles named "ndtom_gaussians" (if any Gaussian qualifies)
/// and, if enabled, a CPointCloudColoured named "ndtom_free_cells".
void buildNdtVisualization(const ndtom::NdtMap& map, const TRenderOptions& options,
                           mrpt::opengl::CSetOfObjects& out);

}  // namespace mrpt_ndtom
