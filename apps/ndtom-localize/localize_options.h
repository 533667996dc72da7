// The command line of ndtom-localize.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "input_format.h"
#include "ndtom/registration.h"
#include "ndtom_io/pose_file.h"

namespace ndtom::localizer {

struct LocalizeOptions {
  std::string map_path;  ///< .ndtom or .ndtommap
  std::string input;
  std::string prefix;  ///< outputs are PREFIX.tum, PREFIX.summary.json, PREFIX.top.png
  mapper::InputFormat format = mapper::InputFormat::Auto;
  std::string poses_file;  ///< the input's own poses (as ndtom-map reads them), if any
  ndtom::io::PoseFormat pose_format = ndtom::io::PoseFormat::Auto;
  size_t max_scans = 0;     ///< first N scans; 0 = all
  uint32_t decimation = 1;  ///< 1 point in N of each scan read

  std::optional<Eigen::Isometry3d> initial;  ///< pose of the first scan's frame in the map
  ndtom::RegistrationOptions registration;

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
