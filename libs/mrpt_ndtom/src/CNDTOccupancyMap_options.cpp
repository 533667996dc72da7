// CNDTOccupancyMap's option structs: .ini loading and saving (MRPT's CLoadableOptions),
// validation through the core, and binary streaming for serialization.
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <optional>
#include <sstream>

#include "archive_checks.h"
#include "ini_values.h"
#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom/map/option_table.h"
#include "ndtom/matching/ndt_likelihood.h"

namespace mrpt_ndtom {
namespace {

// NdtMcl limits: cells beyond 64 map cells describe another scene, and more scan Gaussians
// than this cost milliseconds per particle.
constexpr int32_t kMaxNdtMclFactor = 64;
constexpr int32_t kMaxNdtMclGaussians = 100000;

// Decimations are read as signed integers so that "-1" is reported, not wrapped.
uint32_t readDecimation(const mrpt::config::CConfigFileBase& c, const std::string& section,
                        const std::string& name, uint32_t current) {
  return uint32_t(
      detail::iniInteger(c, section, name, current, 1, TPointExtractionOptions::kMaxDecimation));
}

// Runs a validation and rethrows its message prefixed with the .ini section.
template <class F>
void validateSection(const std::string& section, F&& validate) {
  try {
    validate();
  } catch (const std::invalid_argument& e) {
    THROW_EXCEPTION(mrpt::format("[%s] %s", section.c_str(), e.what()));
  }
}

// Runs a validation of options read from an archive; rethrows naming the option struct.
template <class F>
void validateStored(const char* what, F&& validate) {
  try {
    validate();
  } catch (const std::invalid_argument& e) {
    THROW_EXCEPTION(mrpt::format("%s: %s", what, e.what()));
  }
}

}  // namespace

// --- TInsertionOptions -------------------------------------------------------------------
// The core's options come from its table (ndtom/map/option_table.h), by their row names; the
// decimations are the plugin's own.

namespace {

// One option of the table from the section, read as its type; a missing key keeps `current`.
double readOption(const mrpt::config::CConfigFileBase& source, const std::string& section,
                  const ndtom::OptionRow& row, double current) {
  const std::optional<std::string> text = detail::iniText(source, section, row.name);
  return text ? ndtom::optionFromText(row, row.name, *text) : current;
}

std::string commentOf(const ndtom::OptionRow& row) {
  std::string comment = row.description;
  if (*row.unit) comment += std::string(" [") + row.unit + "]";
  return comment;
}

}  // namespace

void CNDTOccupancyMap::TInsertionOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& source, const std::string& section) {
  for (const ndtom::OptionRow& row : ndtom::kMapOptionRows)
    validateSection(section, [&] {
      const double value = readOption(source, section, row, row.get(*this));
      ndtom::checkOptionValue(row, value);  // here, so that the message names this key
      row.set(*this, value);
    });
  decimation = readDecimation(source, section, "decimation", decimation);
  decimation_3d_range = readDecimation(source, section, "decimation_3d_range", decimation_3d_range);
  validateSection(section, [this] { toMapOptions(); });
}

void CNDTOccupancyMap::TInsertionOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                           const std::string& s) const {
  const int name_width = mrpt::config::MRPT_SAVE_NAME_PADDING();
  const int value_width = mrpt::config::MRPT_SAVE_VALUE_PADDING();
  for (const ndtom::OptionRow& row : ndtom::kMapOptionRows) {
    const double value = row.get(*this);
    switch (row.type) {
      case ndtom::OptionType::Real:
        c.write(s, row.name, value, name_width, value_width, commentOf(row));
        break;
      case ndtom::OptionType::Integer:
        c.write(s, row.name, int64_t(value), name_width, value_width, commentOf(row));
        break;
      case ndtom::OptionType::Bool:
        c.write(s, row.name, value != 0, name_width, value_width, commentOf(row));
        break;
      case ndtom::OptionType::Enum:
        c.write(s, row.name, ndtom::optionValueText(row, value), name_width, value_width,
                commentOf(row));
        break;
    }
  }
  MRPT_SAVE_CONFIG_VAR_COMMENT(decimation, "Keep 1 point in N of scans and point clouds");
  MRPT_SAVE_CONFIG_VAR_COMMENT(decimation_3d_range, "Depth images: use every N-th row and column");
}

void CNDTOccupancyMap::TInsertionOptions::dumpToTextStream(std::ostream& out) const {
  out << "\n----------- [CNDTOccupancyMap::TInsertionOptions] ------------\n\n";
  CLoadableOptions::dumpToTextStream(out);
}

ndtom::MapOptions CNDTOccupancyMap::TInsertionOptions::toMapOptions() const {
  if (decimation < 1 || decimation_3d_range < 1)
    throw std::invalid_argument("decimation: must be >= 1");
  const ndtom::MapOptions& o = *this;
  ndtom::validate(o);
  return o;
}

TPointExtractionOptions CNDTOccupancyMap::TInsertionOptions::extractionOptions() const {
  return {decimation, decimation_3d_range};
}

// A frozen layout, field by field: a new option needs a new version here anyway.
// Version 1 appends threads to version 0.
void CNDTOccupancyMap::TInsertionOptions::writeToStream(mrpt::serialization::CArchive& out) const {
  const uint8_t version = 1;
  out << version << resolution << occupancy.enabled << occupancy.p_hit << occupancy.p_miss
      << occupancy.logodds_min << occupancy.logodds_max << scan.min_range << scan.max_range
      << int32_t(scan.ray_mode) << decimation << decimation_3d_range
      << regularization.min_eigen_ratio << regularization.min_eigen_abs << int32_t(scan.threads);
}

// Reads into a copy and validates it: corrupt data throws (naming the option) and leaves the
// options as they were. Version 0 archives insert with threads = 1, the default. The memory
// budget is not stored: this object's own is kept.
void CNDTOccupancyMap::TInsertionOptions::readFromStream(mrpt::serialization::CArchive& in) {
  uint8_t version;
  in >> version;
  TInsertionOptions read;
  read.scan.memory_budget = scan.memory_budget;
  switch (version) {
    case 0:
    case 1: {
      int32_t mode;
      in >> read.resolution;
      read.occupancy.enabled = detail::readBool(in, "insertionOptions.occupancy_enabled");
      in >> read.occupancy.p_hit >> read.occupancy.p_miss >> read.occupancy.logodds_min >>
          read.occupancy.logodds_max >> read.scan.min_range >> read.scan.max_range >> mode >>
          read.decimation >> read.decimation_3d_range >> read.regularization.min_eigen_ratio >>
          read.regularization.min_eigen_abs;
      if (mode != int32_t(ndtom::RayMode::PerPoint) && mode != int32_t(ndtom::RayMode::PerHitCell))
        THROW_EXCEPTION(mrpt::format("insertionOptions.ray_mode = %d: unknown ray mode", mode));
      read.scan.ray_mode = ndtom::RayMode(mode);
      if (version >= 1) {
        int32_t threads;
        in >> threads;
        read.scan.threads = threads;
      }
    } break;
    default:
      MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
  }
  validateStored("insertionOptions", [&read] { read.toMapOptions(); });
  *this = read;
}

bool CNDTOccupancyMap::TInsertionOptions::operator==(const TInsertionOptions& o) const {
  return static_cast<const ndtom::MapOptions&>(*this) == static_cast<const ndtom::MapOptions&>(o) &&
         decimation == o.decimation && decimation_3d_range == o.decimation_3d_range;
}

// --- TLikelihoodOptions ------------------------------------------------------------------

void CNDTOccupancyMap::TLikelihoodOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& source, const std::string& section) {
  using detail::iniInteger;
  using detail::iniReal;
  likelihood_method = detail::iniEnum(source, section, "likelihood_method", likelihood_method);
  decimation = readDecimation(source, section, "decimation", decimation);
  decimation_3d_range = readDecimation(source, section, "decimation_3d_range", decimation_3d_range);
  outlier_likelihood = iniReal(source, section, "outlier_likelihood", outlier_likelihood);
  search_neighbours = detail::iniBool(source, section, "search_neighbours", search_neighbours);
  min_range = iniReal(source, section, "min_range", min_range);
  max_range = iniReal(source, section, "max_range", max_range, ndtom::NonFinite::Infinity);
  scale = iniReal(source, section, "scale", scale);
  ndt_mcl_scan_factor = int32_t(
      iniInteger(source, section, "ndt_mcl_scan_factor", ndt_mcl_scan_factor, 1, kMaxNdtMclFactor));
  ndt_mcl_map_factor = int32_t(
      iniInteger(source, section, "ndt_mcl_map_factor", ndt_mcl_map_factor, 1, kMaxNdtMclFactor));
  ndt_mcl_max_gaussians = int32_t(iniInteger(source, section, "ndt_mcl_max_gaussians",
                                             ndt_mcl_max_gaussians, 1, kMaxNdtMclGaussians));
  validateSection(section, [this] { validate(); });
}

void CNDTOccupancyMap::TLikelihoodOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                            const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR_COMMENT(likelihood_method,
                               "Points (each point) | NdtMcl (the scan's own NDT, NDT-MCL)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(decimation, "Points: score 1 point in N");
  MRPT_SAVE_CONFIG_VAR_COMMENT(decimation_3d_range,
                               "Points, depth images: score every N-th row and column");
  MRPT_SAVE_CONFIG_VAR_COMMENT(outlier_likelihood,
                               "Floor of a point's / scan Gaussian's likelihood, in (0, 1)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(search_neighbours,
                               "Points: best Gaussian of the 27 cells around a point");
  MRPT_SAVE_CONFIG_VAR_COMMENT(min_range, "Closer points are not used [m]");
  MRPT_SAVE_CONFIG_VAR_COMMENT(max_range, "Farther points are not used [m] (inf: no limit)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(scale,
                               "Multiplies the log-likelihood (< 1 flattens weights), <= 1e280");
  MRPT_SAVE_CONFIG_VAR_COMMENT(ndt_mcl_scan_factor, "NdtMcl: scan cell edge in map cells, [1, 64]");
  MRPT_SAVE_CONFIG_VAR_COMMENT(ndt_mcl_map_factor,
                               "NdtMcl: map coarsening scored against, [1, 64] (1: the map)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(ndt_mcl_max_gaussians,
                               "NdtMcl: scan Gaussians kept (most points), in [1, 100000]");
}

void CNDTOccupancyMap::TLikelihoodOptions::dumpToTextStream(std::ostream& out) const {
  out << "\n----------- [CNDTOccupancyMap::TLikelihoodOptions] ------------\n\n";
  CLoadableOptions::dumpToTextStream(out);
}

void CNDTOccupancyMap::TLikelihoodOptions::validate() const {
  std::ostringstream msg;
  if (decimation < 1 || decimation_3d_range < 1)
    msg << "decimation: must be >= 1";
  else if (!(std::isfinite(min_range) && min_range >= 0))
    msg << "min_range = " << min_range << ": must be finite and >= 0";
  else if (!(max_range > min_range))
    msg << "max_range = " << max_range << ": must be > min_range";
  else if (!(scale > 0 && scale <= kMaxScale))
    msg << "scale = " << scale << ": must be in (0, " << kMaxScale
        << "], which keeps a particle filter's log-likelihoods finite";
  else if (likelihood_method != TLikelihoodMethod::Points &&
           likelihood_method != TLikelihoodMethod::NdtMcl)
    msg << "likelihood_method = " << int32_t(likelihood_method) << ": unknown method";
  else if (ndt_mcl_scan_factor < 1 || ndt_mcl_scan_factor > kMaxNdtMclFactor)
    msg << "ndt_mcl_scan_factor = " << ndt_mcl_scan_factor << ": must be in [1, "
        << kMaxNdtMclFactor << "]";
  else if (ndt_mcl_map_factor < 1 || ndt_mcl_map_factor > kMaxNdtMclFactor)
    msg << "ndt_mcl_map_factor = " << ndt_mcl_map_factor << ": must be in [1, " << kMaxNdtMclFactor
        << "]";
  else if (ndt_mcl_max_gaussians < 1 || ndt_mcl_max_gaussians > kMaxNdtMclGaussians)
    msg << "ndt_mcl_max_gaussians = " << ndt_mcl_max_gaussians << ": must be in [1, "
        << kMaxNdtMclGaussians << "]";
  if (!msg.str().empty()) throw std::invalid_argument(msg.str());
  ndtom::LikelihoodOptions core;
  core.outlier_likelihood = outlier_likelihood;
  ndtom::validate(core);
}

// Version 1 appends the method and the three NdtMcl options to version 0.
void CNDTOccupancyMap::TLikelihoodOptions::writeToStream(mrpt::serialization::CArchive& out) const {
  const uint8_t version = 1;
  out << version << decimation << decimation_3d_range << outlier_likelihood << search_neighbours
      << min_range << max_range << scale << int32_t(likelihood_method) << ndt_mcl_scan_factor
      << ndt_mcl_map_factor << ndt_mcl_max_gaussians;
}

// As TInsertionOptions::readFromStream: validated, unchanged on error. Version 0 archives
// score with the Points method, the only one there was.
void CNDTOccupancyMap::TLikelihoodOptions::readFromStream(mrpt::serialization::CArchive& in) {
  uint8_t version;
  in >> version;
  TLikelihoodOptions read;
  switch (version) {
    case 0:
    case 1:
      in >> read.decimation >> read.decimation_3d_range >> read.outlier_likelihood;
      read.search_neighbours = detail::readBool(in, "likelihoodOptions.search_neighbours");
      in >> read.min_range >> read.max_range >> read.scale;
      if (version >= 1) {
        int32_t method;
        in >> method >> read.ndt_mcl_scan_factor >> read.ndt_mcl_map_factor >>
            read.ndt_mcl_max_gaussians;
        // Checked here, as a number: an enum holding another value is not one of the methods.
        if (method != int32_t(TLikelihoodMethod::Points) &&
            method != int32_t(TLikelihoodMethod::NdtMcl))
          THROW_EXCEPTION(
              mrpt::format("likelihoodOptions.likelihood_method = %d: unknown method", method));
        read.likelihood_method = TLikelihoodMethod(method);
      }
      break;
    default:
      MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
  }
  validateStored("likelihoodOptions", [&read] { read.validate(); });
  *this = read;
}

bool CNDTOccupancyMap::TLikelihoodOptions::operator==(const TLikelihoodOptions& o) const {
  return likelihood_method == o.likelihood_method && decimation == o.decimation &&
         decimation_3d_range == o.decimation_3d_range &&
         outlier_likelihood == o.outlier_likelihood && search_neighbours == o.search_neighbours &&
         min_range == o.min_range && max_range == o.max_range && scale == o.scale &&
         ndt_mcl_scan_factor == o.ndt_mcl_scan_factor &&
         ndt_mcl_map_factor == o.ndt_mcl_map_factor &&
         ndt_mcl_max_gaussians == o.ndt_mcl_max_gaussians;
}

}  // namespace mrpt_ndtom
