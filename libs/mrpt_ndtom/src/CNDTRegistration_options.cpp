// CNDTRegistration's options as an .ini section: the core's names and defaults.
#include <mrpt/config/CConfigFileBase.h>

#include <sstream>

#include "ini_values.h"
#include "mrpt_ndtom/CNDTRegistration.h"

namespace mrpt_ndtom {
namespace {

std::vector<int> parseFactors(const std::string& section, const std::string& text) {
  std::istringstream in(text);
  std::vector<int> factors;
  for (std::string item; in >> item;) {
    if (item[0] == '#' || item[0] == ';') break;
    char* end = nullptr;
    const long value = std::strtol(item.c_str(), &end, 10);
    if (*end != '\0' || value < 1 || value > 1024)
      THROW_EXCEPTION(mrpt::format("[%s] level_factors = %s: expected integers in [1, 1024], "
                                   "coarse to fine, e.g. 16 8 4 2 1",
                                   section.c_str(), text.c_str()));
    factors.push_back(int(value));
  }
  return factors;
}

std::string factorsText(const std::vector<int>& factors) {
  std::string out;
  for (const int f : factors) out += (out.empty() ? "" : " ") + std::to_string(f);
  return out;
}

}  // namespace

void CNDTRegistration::TConfigParams::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& source, const std::string& section) {
  ndtom::RegistrationOptions& o = core;
  try {
    o.method = ndtom::registrationMethodFromString(
        source.read_string(section, "method", ndtom::toString(o.method)));
  } catch (const std::invalid_argument& e) {
    THROW_EXCEPTION(mrpt::format("[%s] %s", section.c_str(), e.what()));
  }
  o.level_factors =
      parseFactors(section, source.read_string(section, "level_factors", factorsText(o.level_factors)));
  o.outlier_ratio = source.read_double(section, "outlier_ratio", o.outlier_ratio);
  o.max_iterations =
      int(detail::readInteger(source, section, "max_iterations", o.max_iterations, 1, 1000));
  o.translation_epsilon = source.read_double(section, "translation_epsilon", o.translation_epsilon);
  o.rotation_epsilon = source.read_double(section, "rotation_epsilon", o.rotation_epsilon);
  o.min_range = source.read_double(section, "min_range", o.min_range);
  o.max_range = source.read_double(section, "max_range", o.max_range);
  o.voxel_ratio = source.read_double(section, "voxel_ratio", o.voxel_ratio);
  o.max_points = size_t(detail::readInteger(source, section, "max_points",
                                            (long long)o.max_points, 10, 100000000));
  o.min_matched_fraction =
      source.read_double(section, "min_matched_fraction", o.min_matched_fraction);
  o.min_judged_fraction =
      source.read_double(section, "min_judged_fraction", o.min_judged_fraction);
  o.max_free_fraction = source.read_double(section, "max_free_fraction", o.max_free_fraction);
  o.planar = source.read_bool(section, "planar", o.planar);
  o.threads = int(detail::readInteger(source, section, "threads", o.threads, 1,
                                      ndtom::ScanOptions::kMaxThreads));
  try {
    ndtom::validate(o);
  } catch (const std::invalid_argument& e) {
    THROW_EXCEPTION(mrpt::format("[%s] %s", section.c_str(), e.what()));
  }
}

void CNDTRegistration::TConfigParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                       const std::string& s) const {
  const ndtom::RegistrationOptions& o = core;
  c.write(s, "method", std::string(ndtom::toString(o.method)), mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "p2d (points to map Gaussians) | d2d (scan NDT)");
  c.write(s, "level_factors", factorsText(o.level_factors), mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "Pyramid levels, coarse to fine, in map cells");
  c.write(s, "outlier_ratio", o.outlier_ratio, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "Expected outlier fraction, in (0, 1)");
  c.write(s, "max_iterations", o.max_iterations, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "Newton iterations per level");
  c.write(s, "translation_epsilon", o.translation_epsilon, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "Stop when a step moves less [m]");
  c.write(s, "rotation_epsilon", o.rotation_epsilon, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "... and turns less [rad]");
  c.write(s, "min_range", o.min_range, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "Scan points closer to the sensor are unused [m]");
  c.write(s, "max_range", o.max_range, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "... and farther ones [m]");
  c.write(s, "voxel_ratio", o.voxel_ratio, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "P2D: scan voxels, fraction of a level's cell");
  c.write(s, "max_points", o.max_points, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "P2D: scan points per level at most");
  c.write(s, "min_matched_fraction", o.min_matched_fraction, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(),
          "Verdict: matched part of what the map can judge, in [0, 1]");
  c.write(s, "min_judged_fraction", o.min_judged_fraction, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(),
          "Verdict: scan share where the map has looked, at least");
  c.write(s, "max_free_fraction", o.max_free_fraction, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "Verdict: scan share in open free space, at most");
  c.write(s, "planar", o.planar, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "Only x, y, yaw (2D)");
  c.write(s, "threads", o.threads, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "Threads, in [1, 256]; same result for any");
}

}  // namespace mrpt_ndtom
