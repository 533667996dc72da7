// Drawing an NDT-OM: each occupied Gaussian as a shaded ellipsoid (k-σ surface, coloured by
// height), all of them batched into one triangle mesh so that tens of thousands draw fast;
// free cells optionally as points. Used by CNDTOccupancyMap::getVisualizationInto() and by
// programs that render maps offscreen.
#pragma once

#include <mrpt/img/color_maps.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdint>
#include <limits>

#include "ndtom/ndt_map.h"

namespace mrpt_ndtom {

struct TRenderOptions {
  /// Ellipsoid surface at this many standard deviations (Default: 1).
  double quantiles = 1.0;
  /// Sphere tessellation: 0 = octahedron (8 triangles), each level ×4 (Default: 1, 32).
  uint32_t subdivisions = 1;
  /// Gaussians drawn at most; beyond that those with the most points are kept
  /// (Default: 50000, ~170 MB of triangles at subdivision 1).
  uint32_t max_ellipsoids = 50000;
  /// Only cells with log-odds above this are drawn (Default: 0, i.e. p > 0.5).
  double min_logodds = 0.0;
  /// Colour range in z (m); NaN picks the 2nd and 98th percentiles of the drawn means
  /// (Default: NaN, NaN).
  double color_min_z = std::numeric_limits<double>::quiet_NaN();
  double color_max_z = std::numeric_limits<double>::quiet_NaN();
  mrpt::img::TColormap colormap = mrpt::img::cmJET;
  /// Draw free cells (log-odds < 0) as points at their centres (Default: false).
  bool show_free_cells = false;
  uint32_t max_free_cells = 1000000;  ///< (Default: 1e6; evenly thinned beyond)
  float free_cell_point_size = 2.0f;  ///< pixels (Default: 2)

  /// Throws std::invalid_argument naming a bad value.
  void validate() const;
  void writeToStream(mrpt::serialization::CArchive& out) const;
  void readFromStream(mrpt::serialization::CArchive& in);
  bool operator==(const TRenderOptions& o) const;
};

/// Triangles drawn per ellipsoid at `subdivisions` (see TRenderOptions): 8·4^subdivisions.
size_t trianglesPerEllipsoid(uint32_t subdivisions);

/// Appends to `out` a CSetOfTriangles named "ndtom_gaussians" (if any Gaussian qualifies)
/// and, if enabled, a CPointCloudColoured named "ndtom_free_cells".
void buildNdtVisualization(const ndtom::NdtMap& map, const TRenderOptions& options,
                           mrpt::opengl::CSetOfObjects& out);

}  // namespace mrpt_ndtom
