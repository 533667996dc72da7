// CNDTOccupancyMap's option structs: .ini loading and saving (MRPT's CLoadableOptions),
// validation through the core, and binary streaming for serialization.
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/serialization/CArchive.h>

#include <cctype>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "archive_checks.h"
#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom/ndt_likelihood.h"

namespace mrpt_ndtom {
namespace {

// Decimations are read as signed integers so that "-1" is reported, not wrapped.
uint32_t readDecimation(const mrpt::config::CConfigFileBase& c, const std::string& section,
                        const std::string& name, uint32_t current) {
  const int value = c.read_int(section, name, int(current));
  if (value < 1)
    THROW_EXCEPTION(
        mrpt::format("[%s] %s = %d: must be >= 1", section.c_str(), name.c_str(), value));
  return uint32_t(value);
}

// Read as text: read_int's atoi takes "4294967298" as 2 and "1e3" as 1. MRPT leaves "#" and
// ";" comments in the value, so they may follow the number. The range is checked by the core.
int readThreads(const mrpt::config::CConfigFileBase& c, const std::string& section, int current) {
  const std::string text = c.read_string(section, "threads", std::to_string(current));
  char* end = nullptr;
  const long long value = std::strtoll(text.c_str(), &end, 10);
  const char* rest = end;
  while (std::isspace(static_cast<unsigned char>(*rest))) ++rest;
  if (end == text.c_str() || (*rest != '\0' && *rest != '#' && *rest != ';') || value < INT_MIN ||
      value > INT_MAX)  // strtoll saturates on overflow
    THROW_EXCEPTION(mrpt::format("[%s] threads = %s: must be an integer in [1, 256]",
                                 section.c_str(), text.c_str()));
  return int(value);
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

void CNDTOccupancyMap::TInsertionOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& source, const std::string& section) {
  MRPT_LOAD_CONFIG_VAR(resolution, double, source, section);
  MRPT_LOAD_CONFIG_VAR(occupancy_enabled, bool, source, section);
  MRPT_LOAD_CONFIG_VAR(p_hit, double, source, section);
  MRPT_LOAD_CONFIG_VAR(p_miss, double, source, section);
  MRPT_LOAD_CONFIG_VAR(logodds_min, double, source, section);
  MRPT_LOAD_CONFIG_VAR(logodds_max, double, source, section);
  MRPT_LOAD_CONFIG_VAR(min_range, double, source, section);
  MRPT_LOAD_CONFIG_VAR(max_range, double, source, section);
  ray_mode = source.read_enum<ndtom::RayMode>(section, "ray_mode", ray_mode);
  decimation = readDecimation(source, section, "decimation", decimation);
  decimation_3d_range = readDecimation(source, section, "decimation_3d_range", decimation_3d_range);
  MRPT_LOAD_CONFIG_VAR(min_eigen_ratio, double, source, section);
  MRPT_LOAD_CONFIG_VAR(min_eigen_abs, double, source, section);
  threads = readThreads(source, section, threads);
  MRPT_LOAD_CONFIG_VAR(memory_budget, double, source, section);
  validateSection(section, [this] { toMapOptions(); });
}

void CNDTOccupancyMap::TInsertionOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                           const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR_COMMENT(resolution, "Cell edge [m]");
  MRPT_SAVE_CONFIG_VAR_COMMENT(occupancy_enabled,
                               "Occupancy by ray tracing (Eq. 12); false: Recursive NDT");
  MRPT_SAVE_CONFIG_VAR_COMMENT(p_hit, "p_o: occupancy of a cell with hits, in (0.5, 1)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(p_miss, "p_e: occupancy of a cell a ray crosses, in (0, 0.5)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(logodds_min, "Lower log-odds clamp (< 0)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(logodds_max, "Upper log-odds clamp (> 0)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(min_range, "Closer points are dropped [m]");
  MRPT_SAVE_CONFIG_VAR_COMMENT(max_range,
                               "Farther points: free ray up to here, no hit [m] (inf: no limit)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(ray_mode, "PerPoint (one ray per point) | PerHitCell (faster)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(decimation, "Keep 1 point in N of scans and point clouds");
  MRPT_SAVE_CONFIG_VAR_COMMENT(decimation_3d_range, "Depth images: use every N-th row and column");
  MRPT_SAVE_CONFIG_VAR_COMMENT(min_eigen_ratio,
                               "Covariance eigenvalue floor, relative to the largest");
  MRPT_SAVE_CONFIG_VAR_COMMENT(min_eigen_abs, "Covariance eigenvalue floor [m^2]");
  MRPT_SAVE_CONFIG_VAR_COMMENT(threads, "Threads inserting a scan, in [1, 256]; same map for any");
  MRPT_SAVE_CONFIG_VAR_COMMENT(memory_budget,
                               "MB the map and a scan may take; larger scans are refused");
}

ndtom::MapOptions CNDTOccupancyMap::TInsertionOptions::toMapOptions() const {
  if (decimation < 1 || decimation_3d_range < 1)
    throw std::invalid_argument("decimation: must be >= 1");
  ndtom::MapOptions o;
  o.resolution = resolution;
  o.occupancy.enabled = occupancy_enabled;
  o.occupancy.p_hit = p_hit;
  o.occupancy.p_miss = p_miss;
  o.occupancy.logodds_min = logodds_min;
  o.occupancy.logodds_max = logodds_max;
  o.insertion.min_range = min_range;
  o.insertion.max_range = max_range;
  o.insertion.ray_mode = ray_mode;
  o.insertion.threads = threads;
  if (!(memory_budget >= 1 && memory_budget <= 1e12))  // before the conversion to bytes
    throw std::invalid_argument("memory_budget = " + std::to_string(memory_budget) +
                                ": must be in [1, 1e12] MB");
  o.insertion.memory_budget = uint64_t(memory_budget * 1e6);
  o.regularization.min_eigen_ratio = min_eigen_ratio;
  o.regularization.min_eigen_abs = min_eigen_abs;
  ndtom::validate(o);
  return o;
}

TPointExtractionOptions CNDTOccupancyMap::TInsertionOptions::extractionOptions() const {
  return {decimation, decimation_3d_range};
}

// Version 1 appends threads to version 0.
void CNDTOccupancyMap::TInsertionOptions::writeToStream(mrpt::serialization::CArchive& out) const {
  const uint8_t version = 1;
  out << version << resolution << occupancy_enabled << p_hit << p_miss << logodds_min << logodds_max
      << min_range << max_range << int32_t(ray_mode) << decimation << decimation_3d_range
      << min_eigen_ratio << min_eigen_abs << threads;
}

// Reads into a copy and validates it: corrupt data throws (naming the option) and leaves the
// options as they were. Version 0 archives insert with threads = 1, the default. The memory
// budget is not stored: this object's own is kept.
void CNDTOccupancyMap::TInsertionOptions::readFromStream(mrpt::serialization::CArchive& in) {
  uint8_t version;
  in >> version;
  TInsertionOptions read;
  read.memory_budget = memory_budget;
  switch (version) {
    case 0:
    case 1: {
      int32_t mode;
      in >> read.resolution;
      read.occupancy_enabled = detail::readBool(in, "insertionOptions.occupancy_enabled");
      in >> read.p_hit >> read.p_miss >> read.logodds_min >> read.logodds_max >> read.min_range >>
          read.max_range >> mode >> read.decimation >> read.decimation_3d_range >>
          read.min_eigen_ratio >> read.min_eigen_abs;
      if (mode != int32_t(ndtom::RayMode::PerPoint) && mode != int32_t(ndtom::RayMode::PerHitCell))
        THROW_EXCEPTION(mrpt::format("insertionOptions.ray_mode = %d: unknown ray mode", mode));
      read.ray_mode = ndtom::RayMode(mode);
      if (version >= 1) in >> read.threads;
    } break;
    default:
      MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
  }
  validateStored("insertionOptions", [&read] { read.toMapOptions(); });
  *this = read;
}

bool CNDTOccupancyMap::TInsertionOptions::operator==(const TInsertionOptions& o) const {
  return resolution == o.resolution && occupancy_enabled == o.occupancy_enabled &&
         p_hit == o.p_hit && p_miss == o.p_miss && logodds_min == o.logodds_min &&
         logodds_max == o.logodds_max && min_range == o.min_range && max_range == o.max_range &&
         ray_mode == o.ray_mode && decimation == o.decimation &&
         decimation_3d_range == o.decimation_3d_range && min_eigen_ratio == o.min_eigen_ratio &&
         min_eigen_abs == o.min_eigen_abs && threads == o.threads &&
         memory_budget == o.memory_budget;
}

// --- TLikelihoodOptions ------------------------------------------------------------------

void CNDTOccupancyMap::TLikelihoodOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& source, const std::string& section) {
  decimation = readDecimation(source, section, "decimation", decimation);
  decimation_3d_range = readDecimation(source, section, "decimation_3d_range", decimation_3d_range);
  MRPT_LOAD_CONFIG_VAR(outlier_likelihood, double, source, section);
  MRPT_LOAD_CONFIG_VAR(search_neighbours, bool, source, section);
  MRPT_LOAD_CONFIG_VAR(min_range, double, source, section);
  MRPT_LOAD_CONFIG_VAR(max_range, double, source, section);
  MRPT_LOAD_CONFIG_VAR(scale, double, source, section);
  validateSection(section, [this] { validate(); });
}

void CNDTOccupancyMap::TLikelihoodOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                            const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR_COMMENT(decimation, "Score 1 point in N");
  MRPT_SAVE_CONFIG_VAR_COMMENT(decimation_3d_range,
                               "Depth images: score every N-th row and column");
  MRPT_SAVE_CONFIG_VAR_COMMENT(outlier_likelihood, "Floor of a point's likelihood, in (0, 1)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(search_neighbours,
                               "Best Gaussian of the 27 cells around a point (else own cell)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(min_range, "Closer points are not scored [m]");
  MRPT_SAVE_CONFIG_VAR_COMMENT(max_range, "Farther points are not scored [m] (inf: no limit)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(scale, "Multiplies the log-likelihood (< 1 flattens weights)");
}

void CNDTOccupancyMap::TLikelihoodOptions::validate() const {
  std::ostringstream msg;
  if (decimation < 1 || decimation_3d_range < 1)
    msg << "decimation: must be >= 1";
  else if (!(std::isfinite(min_range) && min_range >= 0))
    msg << "min_range = " << min_range << ": must be finite and >= 0";
  else if (!(max_range > min_range))
    msg << "max_range = " << max_range << ": must be > min_range";
  else if (!(std::isfinite(scale) && scale > 0))
    msg << "scale = " << scale << ": must be finite and > 0";
  if (!msg.str().empty()) throw std::invalid_argument(msg.str());
  ndtom::LikelihoodOptions core;
  core.outlier_likelihood = outlier_likelihood;
  ndtom::validate(core);
}

void CNDTOccupancyMap::TLikelihoodOptions::writeToStream(mrpt::serialization::CArchive& out) const {
  const uint8_t version = 0;
  out << version << decimation << decimation_3d_range << outlier_likelihood << search_neighbours
      << min_range << max_range << scale;
}

// As TInsertionOptions::readFromStream: validated, unchanged on error.
void CNDTOccupancyMap::TLikelihoodOptions::readFromStream(mrpt::serialization::CArchive& in) {
  uint8_t version;
  in >> version;
  TLikelihoodOptions read;
  switch (version) {
    case 0:
      in >> read.decimation >> read.decimation_3d_range >> read.outlier_likelihood;
      read.search_neighbours = detail::readBool(in, "likelihoodOptions.search_neighbours");
      in >> read.min_range >> read.max_range >> read.scale;
      break;
    default:
      MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
  }
  validateStored("likelihoodOptions", [&read] { read.validate(); });
  *this = read;
}

bool CNDTOccupancyMap::TLikelihoodOptions::operator==(const TLikelihoodOptions& o) const {
  return decimation == o.decimation && decimation_3d_range == o.decimation_3d_range &&
         outlier_likelihood == o.outlier_likelihood && search_neighbours == o.search_neighbours &&
         min_range == o.min_range && max_range == o.max_range && scale == o.scale;
}

}  // namespace mrpt_ndtom
