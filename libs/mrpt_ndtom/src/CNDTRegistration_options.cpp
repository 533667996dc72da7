// CNDTRegistration's options as an .ini section: the core's names and defaults.
#include <mrpt/config/CConfigFileBase.h>

#include <sstream>

#include "ini_values.h"
#include "mrpt_ndtom/CNDTRegistration.h"

namespace mrpt_ndtom {
namespace {

// "16 8 4 2 1": each word an integer of the core's reader; the order is checked by validate.
std::vector<int> parseFactors(const std::string& text) {
  std::istringstream in(text);
  std::vector<int> factors;
  for (std::string item; in >> item;)
    factors.push_back(int(ndtom::integerFromText("level_factors", item, 1, 1024)));
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
  using detail::iniInteger;
  using detail::iniReal;
  ndtom::RegistrationOptions& o = core;
  o.method = detail::iniValue(source, section, "method", o.method, [](const std::string& text) {
    return ndtom::registrationMethodFromString(text);
  });
  o.level_factors =
      detail::iniValue(source, section, "level_factors", o.level_factors, parseFactors);
  o.outlier_ratio = iniReal(source, section, "outlier_ratio", o.outlier_ratio);
  o.max_iterations = int(iniInteger(source, section, "max_iterations", o.max_iterations, 1, 1000));
  o.translation_epsilon = iniReal(source, section, "translation_epsilon", o.translation_epsilon);
  o.rotation_epsilon = iniReal(source, section, "rotation_epsilon", o.rotation_epsilon);
  o.min_range = iniReal(source, section, "min_range", o.min_range);
  o.max_range = iniReal(source, section, "max_range", o.max_range, ndtom::NonFinite::Infinity);
  o.voxel_ratio = iniReal(source, section, "voxel_ratio", o.voxel_ratio);
  o.max_points =
      size_t(iniInteger(source, section, "max_points", (long long)o.max_points, 10, 100000000));
  o.min_matched_fraction = iniReal(source, section, "min_matched_fraction", o.min_matched_fraction);
  o.min_judged_fraction = iniReal(source, section, "min_judged_fraction", o.min_judged_fraction);
  o.max_free_fraction = iniReal(source, section, "max_free_fraction", o.max_free_fraction);
  o.planar = detail::iniBool(source, section, "planar", o.planar);
  o.threads =
      int(iniInteger(source, section, "threads", o.threads, 1, ndtom::ScanOptions::kMaxThreads));
  try {
    ndtom::validate(o);
  } catch (const std::invalid_argument& e) {
    THROW_EXCEPTION(mrpt::format("[%s] %s", section.c_str(), e.what()));
  }
}

void CNDTRegistration::TConfigParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                       const std::string& s) const {
  const ndtom::RegistrationOptions& o = core;
  c.write(s, "method", std::string(ndtom::toString(o.method)),
          mrpt::config::MRPT_SAVE_NAME_PADDING(), mrpt::config::MRPT_SAVE_VALUE_PADDING(),
          "p2d (points to map Gaussians) | d2d (scan NDT)");
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
          mrpt::config::MRPT_SAVE_VALUE_PADDING(),
          "Scan points closer to the sensor are unused [m]");
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
          mrpt::config::MRPT_SAVE_VALUE_PADDING(),
          "Verdict: scan share in open free space, at most");
  c.write(s, "planar", o.planar, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "Only x, y, yaw (2D)");
  c.write(s, "threads", o.threads, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "Threads, in [1, 256]; same result for any");
}

}  // namespace mrpt_ndtom
