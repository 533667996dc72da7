// CMetricMapBuilderNDT's options as .ini sections: the registration's keys are
// CNDTRegistration's (one reader for both), the map's CNDTOccupancyMap's.
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <iostream>

#include "ini_values.h"
#include "mrpt_ndtom/CMetricMapBuilderNDT.h"
#include "mrpt_ndtom/CNDTRegistration.h"

namespace mrpt_ndtom {
namespace {

constexpr int kMaxGroundThinning = 1000;  // as ndtom-slam's --ground-thinning

void writeKey(mrpt::config::CConfigFileBase& c, const std::string& section, const std::string& name,
              double value, const std::string& comment) {
  c.write(section, name, value, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), comment);
}

void writeKey(mrpt::config::CConfigFileBase& c, const std::string& section, const std::string& name,
              bool value, const std::string& comment) {
  c.write(section, name, value, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), comment);
}

void writeKey(mrpt::config::CConfigFileBase& c, const std::string& section, const std::string& name,
              int value, const std::string& comment) {
  c.write(section, name, value, mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), comment);
}

}  // namespace

std::string CMetricMapBuilderNDT::TConfigParams::mapSection(const std::string& section) {
  return section + "_ndtOccupancyMap_00_insertOpts";
}

void CMetricMapBuilderNDT::TConfigParams::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& source, const std::string& section) {
  using detail::iniInteger;
  using detail::iniReal;
  // Into copies: a bad value leaves the options as they were.
  CNDTOccupancyMap::TInsertionOptions map = mapOptions;
  map.loadFromConfigFile(source, mapSection(section));
  ndtom::OnlineMapperOptions o = online;
  // The registration's keys, `threads` included: the online mapper's threads.
  CNDTRegistration::TConfigParams registration;
  registration.core = o.placement.registration;
  registration.core.threads = o.threads;
  registration.loadFromConfigFile(source, section);
  o.placement.registration = registration.core;
  o.threads = registration.core.threads;
  o.placement.recovery_radius =
      iniReal(source, section, "recovery_radius", o.placement.recovery_radius);
  o.placement.recovery_yaw_deg =
      iniReal(source, section, "recovery_yaw_deg", o.placement.recovery_yaw_deg);
  o.placement.weak_direction_sigma =
      iniReal(source, section, "weak_direction_sigma", o.placement.weak_direction_sigma,
              ndtom::NonFinite::Infinity);
  o.placement.ground_thinning = int(iniInteger(source, section, "ground_thinning",
                                               o.placement.ground_thinning, 1, kMaxGroundThinning));
  o.placement.retry_without_finest = detail::iniBool(source, section, "retry_without_finest",
                                                     o.placement.retry_without_finest);
  o.target_radius = iniReal(source, section, "target_radius", o.target_radius);
  o.target_refresh_distance =
      iniReal(source, section, "target_refresh_distance", o.target_refresh_distance);
  o.free_space_overrule = iniReal(source, section, "free_space_overrule", o.free_space_overrule);
  try {
    ndtom::OnlineMapperOptions check = o;
    check.map = map.toMapOptions();
    ndtom::validate(check);
  } catch (const std::invalid_argument& e) {
    detail::throwInSection(section, e);
  }
  mapOptions = map;
  online = o;
}

void CMetricMapBuilderNDT::TConfigParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                           const std::string& s) const {
  CNDTRegistration::TConfigParams registration;
  registration.core = online.placement.registration;
  registration.core.threads = online.threads;
  registration.saveToConfigFile(c, s);
  const ndtom::PlacementOptions& p = online.placement;
  writeKey(c, s, "recovery_radius", p.recovery_radius,
           "Verdict failed: search x, y within this radius [m]");
  writeKey(c, s, "recovery_yaw_deg", p.recovery_yaw_deg, "... and yaw within +- this [deg]");
  writeKey(c, s, "weak_direction_sigma", p.weak_direction_sigma,
           "Directions less constrained (std. dev.) keep the prediction [m] (inf: never)");
  writeKey(c, s, "ground_thinning", p.ground_thinning,
           "One in K points of the scan's ground plane registers, in [1, 1000]");
  writeKey(c, s, "retry_without_finest", p.retry_without_finest,
           "A scan the whole pyramid cannot place is tried without its finest level");
  writeKey(c, s, "target_radius", online.target_radius,
           "Register against the map within this distance [m]");
  writeKey(c, s, "target_refresh_distance", online.target_refresh_distance,
           "Move that region with the sensor after this travel [m] (0: every scan)");
  writeKey(c, s, "free_space_overrule", online.free_space_overrule,
           "Place a scan only free space refuses within this distance of the prediction [m]");
  mapOptions.saveToConfigFile(c, mapSection(s));
}

void CMetricMapBuilderNDT::TConfigParams::dumpToTextStream(std::ostream& out) const {
  out << "\n----------- [CMetricMapBuilderNDT::TConfigParams] ------------\n\n";
  CLoadableOptions::dumpToTextStream(out);
}

std::vector<std::string> CMetricMapBuilderNDT::TConfigParams::keys() {
  mrpt::config::CConfigFileMemory memory;
  TConfigParams().saveToConfigFile(memory, "s");
  std::vector<std::string> keys;
  memory.getAllKeys("s", keys);
  for (std::string& key : keys)  // MRPT pads saved keys to a column
    key.erase(std::find_if(key.rbegin(), key.rend(), [](char ch) { return ch != ' '; }).base(),
              key.end());
  return keys;
}

bool CMetricMapBuilderNDT::TConfigParams::operator==(const TConfigParams& o) const {
  const ndtom::RegistrationOptions& r = online.placement.registration;
  const ndtom::RegistrationOptions& q = o.online.placement.registration;
  const ndtom::PlacementOptions& p = online.placement;
  const ndtom::PlacementOptions& x = o.online.placement;
  return mapOptions == o.mapOptions && r.method == q.method && r.level_factors == q.level_factors &&
         r.outlier_ratio == q.outlier_ratio && r.max_iterations == q.max_iterations &&
         r.translation_epsilon == q.translation_epsilon &&
         r.rotation_epsilon == q.rotation_epsilon && r.min_range == q.min_range &&
         r.max_range == q.max_range && r.voxel_ratio == q.voxel_ratio &&
         r.max_points == q.max_points && r.min_matched_fraction == q.min_matched_fraction &&
         r.min_judged_fraction == q.min_judged_fraction &&
         r.max_free_fraction == q.max_free_fraction && r.planar == q.planar &&
         p.recovery_radius == x.recovery_radius && p.recovery_yaw_deg == x.recovery_yaw_deg &&
         p.weak_direction_sigma == x.weak_direction_sigma &&
         p.ground_thinning == x.ground_thinning &&
         p.retry_without_finest == x.retry_without_finest && online.target_radius == o.online.target_radius &&
         online.target_refresh_distance == o.online.target_refresh_distance &&
         online.free_space_overrule == o.online.free_space_overrule &&
         online.threads == o.online.threads;
}

}  // namespace mrpt_ndtom
