// The command line of ndtom-localize.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "ndtom/registration/registration.h"
#include "ndtom_apps/input_format.h"
#include "ndtom_io/pose_file.h"
#include "tracking.h"

namespace ndtom::localizer {

struct LocalizeOptions {
  std::string map_path;  ///< .ndtom, .ndtommap or a tiled map
  double region_radius = 60;  ///< m: tiles of a tiled map kept resident around the robot
  std::string input;
  std::string prefix;  ///< outputs are PREFIX.tum, PREFIX.summary.json, PREFIX.top.png
  apps::InputFormat format = apps::InputFormat::Auto;
  std::string poses_file;  ///< the input's own poses (as ndtom-map reads them), if any
  ndtom::io::PoseFormat pose_format = ndtom::io::PoseFormat::Auto;
  double pose_time_tolerance = 0.02;
  size_t skip = 0;          ///< scans read and left out first
  size_t max_scans = 0;     ///< first N scans; 0 = all
  uint32_t decimation = 1;  ///< 1 point in N of each scan read

  std::string reference_file;  ///< --reference: poses to compare with (KITTI or TUM)
  ndtom::io::PoseFormat reference_format = ndtom::io::PoseFormat::Auto;
  double reference_time_tolerance = 0.02;  ///< s, TUM reference matched by time stamp

  /// --initial, --relocalize, the registration and the searches.
  TrackingSettings tracking;

  std::string save_map_prefix;  ///< --save-map: PREFIX.ndtom, the prior map extended

  bool pictures = true;
  int image_width = 1200;
  bool quiet = false;
  bool help = false;
};

/// Throws apps::UsageError with a one-line message for unknown options, missing or bad values.
LocalizeOptions parseLocalizeOptions(int argc, char** argv);
std::string helpText();

/// "x y z qx qy qz qw" (TUM's order) as a pose; throws apps::UsageError naming `option`.
Eigen::Isometry3d parsePose(const std::string& option, const std::string& text);

}  // namespace ndtom::localizer
