// TRenderOptions: validation, .ini loading and saving, binary streaming.
#include "mrpt_ndtom/render_options.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "archive_checks.h"
#include "ini_values.h"

namespace mrpt_ndtom {
namespace {

constexpr uint32_t kMaxSubdivisions = 4;  // 2048 triangles per ellipsoid

bool isColormap(int32_t value) {
  return value >= int32_t(mrpt::img::cmNONE) && value <= int32_t(mrpt::img::cmHOT);
}

}  // namespace

void TRenderOptions::validate() const {
  std::ostringstream msg;
  if (!(std::isfinite(quantiles) && quantiles > 0))
    msg << "quantiles = " << quantiles << ": must be finite and > 0";
  else if (subdivisions > kMaxSubdivisions)
    msg << "subdivisions = " << subdivisions << ": must be <= " << kMaxSubdivisions;
  else if (!(std::isfinite(free_cell_point_size) && free_cell_point_size > 0))
    msg << "free_cell_point_size = " << free_cell_point_size << ": must be finite and > 0";
  else if (std::isnan(min_logodds))
    msg << "min_logodds: must not be NaN";
  else if (!isColormap(int32_t(colormap)))
    msg << "colormap = " << int32_t(colormap) << ": unknown colormap";
  if (!msg.str().empty()) throw std::invalid_argument(msg.str());
}

void TRenderOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                        const std::string& section) {
  using detail::iniBool;
  using detail::iniInteger;
  using detail::iniReal;
  using ndtom::NonFinite;
  TRenderOptions read = *this;  // a bad value leaves the options as they were
  read.quantiles = iniReal(source, section, "quantiles", quantiles);
  read.subdivisions =
      uint32_t(iniInteger(source, section, "subdivisions", subdivisions, 0, kMaxSubdivisions));
  read.max_ellipsoids =
      uint32_t(iniInteger(source, section, "max_ellipsoids", max_ellipsoids, 0, UINT32_MAX));
  // -inf draws every cell with a Gaussian; nan picks the colour range from the map.
  read.min_logodds = iniReal(source, section, "min_logodds", min_logodds, NonFinite::Infinity);
  read.color_min_z = iniReal(source, section, "color_min_z", color_min_z, NonFinite::Nan);
  read.color_max_z = iniReal(source, section, "color_max_z", color_max_z, NonFinite::Nan);
  read.colormap = detail::iniEnum(source, section, "colormap", colormap);
  read.show_free_cells = iniBool(source, section, "show_free_cells", show_free_cells);
  read.max_free_cells =
      uint32_t(iniInteger(source, section, "max_free_cells", max_free_cells, 0, UINT32_MAX));
  // As a double: a float would turn 1e39 into inf, which validate() then refuses.
  read.free_cell_point_size =
      float(iniReal(source, section, "free_cell_point_size", free_cell_point_size));
  read.generate_occupied_voxels =
      iniBool(source, section, "generate_occupied_voxels", generate_occupied_voxels);
  read.visible_occupied_voxels =
      iniBool(source, section, "visible_occupied_voxels", visible_occupied_voxels);
  read.generate_free_voxels =
      iniBool(source, section, "generate_free_voxels", generate_free_voxels);
  read.visible_free_voxels = iniBool(source, section, "visible_free_voxels", visible_free_voxels);
  try {
    read.validate();
  } catch (const std::invalid_argument& e) {
    THROW_EXCEPTION(mrpt::format("[%s] %s", section.c_str(), e.what()));
  }
  *this = read;
}

void TRenderOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                      const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR_COMMENT(quantiles, "Ellipsoid surface at this many standard deviations");
  MRPT_SAVE_CONFIG_VAR_COMMENT(subdivisions, "Sphere tessellation, 0-4: 8*4^N triangles");
  MRPT_SAVE_CONFIG_VAR_COMMENT(max_ellipsoids, "Most Gaussians drawn (those with most points)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(min_logodds, "Only cells with log-odds above this are drawn");
  MRPT_SAVE_CONFIG_VAR_COMMENT(color_min_z, "Colour range in z [m]; nan: 2nd percentile");
  MRPT_SAVE_CONFIG_VAR_COMMENT(color_max_z, "Colour range in z [m]; nan: 98th percentile");
  MRPT_SAVE_CONFIG_VAR_COMMENT(colormap, "cmJET | cmHOT | cmGRAYSCALE | cmNONE");
  MRPT_SAVE_CONFIG_VAR_COMMENT(show_free_cells, "Free cells as points");
  MRPT_SAVE_CONFIG_VAR_COMMENT(max_free_cells, "Most free cells drawn (evenly thinned)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(free_cell_point_size, "Point size of free cells [px]");
  MRPT_SAVE_CONFIG_VAR_COMMENT(generate_occupied_voxels, "getAsOctoMapVoxels: occupied set");
  MRPT_SAVE_CONFIG_VAR_COMMENT(visible_occupied_voxels, "getAsOctoMapVoxels: show it");
  MRPT_SAVE_CONFIG_VAR_COMMENT(generate_free_voxels, "getAsOctoMapVoxels: free set");
  MRPT_SAVE_CONFIG_VAR_COMMENT(visible_free_voxels, "getAsOctoMapVoxels: show it");
}

void TRenderOptions::dumpToTextStream(std::ostream& out) const {
  out << "\n----------- [mrpt_ndtom::TRenderOptions] ------------\n\n";
  CLoadableOptions::dumpToTextStream(out);
}

// Version 1 appends the voxel sets' flags to version 0.
void TRenderOptions::writeToStream(mrpt::serialization::CArchive& out) const {
  const uint8_t version = 1;
  out << version << quantiles << subdivisions << max_ellipsoids << min_logodds << color_min_z
      << color_max_z << int32_t(colormap) << show_free_cells << max_free_cells
      << free_cell_point_size << generate_occupied_voxels << visible_occupied_voxels
      << generate_free_voxels << visible_free_voxels;
}

// Reads into a copy and validates it: corrupt data throws (naming the option) and leaves the
// options as they were.
void TRenderOptions::readFromStream(mrpt::serialization::CArchive& in) {
  uint8_t version;
  in >> version;
  TRenderOptions read;
  switch (version) {
    case 0:
    case 1: {
      int32_t cmap;
      in >> read.quantiles >> read.subdivisions >> read.max_ellipsoids >> read.min_logodds >>
          read.color_min_z >> read.color_max_z >> cmap;
      read.show_free_cells = detail::readBool(in, "renderOptions.show_free_cells");
      in >> read.max_free_cells >> read.free_cell_point_size;
      // Not every int is a TColormap (an unscoped enum without a fixed type): check first.
      if (!isColormap(cmap))
        THROW_EXCEPTION(mrpt::format("renderOptions.colormap = %d: unknown colormap", cmap));
      read.colormap = mrpt::img::TColormap(cmap);
      if (version >= 1) {
        read.generate_occupied_voxels =
            detail::readBool(in, "renderOptions.generate_occupied_voxels");
        read.visible_occupied_voxels =
            detail::readBool(in, "renderOptions.visible_occupied_voxels");
        read.generate_free_voxels = detail::readBool(in, "renderOptions.generate_free_voxels");
        read.visible_free_voxels = detail::readBool(in, "renderOptions.visible_free_voxels");
      }
    } break;
    default:
      MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
  }
  try {
    read.validate();
  } catch (const std::invalid_argument& e) {
    THROW_EXCEPTION(std::string("renderOptions: ") + e.what());
  }
  *this = read;
}

bool TRenderOptions::operator==(const TRenderOptions& o) const {
  auto same = [](double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); };
  return quantiles == o.quantiles && subdivisions == o.subdivisions &&
         max_ellipsoids == o.max_ellipsoids && min_logodds == o.min_logodds &&
         same(color_min_z, o.color_min_z) && same(color_max_z, o.color_max_z) &&
         colormap == o.colormap && show_free_cells == o.show_free_cells &&
         max_free_cells == o.max_free_cells && free_cell_point_size == o.free_cell_point_size &&
         generate_occupied_voxels == o.generate_occupied_voxels &&
         visible_occupied_voxels == o.visible_occupied_voxels &&
         generate_free_voxels == o.generate_free_voxels &&
         visible_free_voxels == o.visible_free_voxels;
}

}  // namespace mrpt_ndtom
