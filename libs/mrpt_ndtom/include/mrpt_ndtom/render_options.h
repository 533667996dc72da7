// How CNDTOccupancyMap draws itself: the ellipsoids of getVisualizationInto() and the voxels
// of getAsOctoMapVoxels(). In .ini files: the section [<map prefix>_renderOpts].
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/img/color_maps.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdint>
#include <limits>

namespace mrpt_ndtom {

struct TRenderOptions : public mrpt::config::CLoadableOptions {
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

  /// getAsOctoMapVoxels(): which voxel sets it fills and which it shows (as
  /// COccupancyGridMap3D's renderingOptions; Default: all true).
  bool generate_occupied_voxels = true;
  bool visible_occupied_voxels = true;
  bool generate_free_voxels = true;
  bool visible_free_voxels = true;

  /// Throws (naming the section and option) if a loaded value is invalid.
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                          const std::string& section) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                        const std::string& section) const override;
  /// The options under a header naming them, as MRPT's own options print.
  void dumpToTextStream(std::ostream& out) const override;

  /// Throws std::invalid_argument naming a bad value.
  void validate() const;
  void writeToStream(mrpt::serialization::CArchive& out) const;
  void readFromStream(mrpt::serialization::CArchive& in);
  bool operator==(const TRenderOptions& o) const;
};

}  // namespace mrpt_ndtom
