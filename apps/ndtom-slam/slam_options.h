// The command line of ndtom-slam: ndtom-map's (input, map options, outputs) without the
// options that give or replay poses, and the online mapper's own.
#pragma once

#include <string>

#include "loop_closure.h"
#include "ndtom/online/online_mapper.h"
#include "ndtom_apps/mapper_options.h"

namespace ndtom::slam {

/// --config's section when --section is not given: share/mrpt/ndtom-slam.ini's.
inline const std::string kDefaultSlamSection = "NDTSLAM";

struct SlamOptions {
  mapper::MapperOptions map;  ///< input, --config and map keys, outputs
  /// Registration and recovery (resolution, threads and the map come from `map`).
  ndtom::OnlineMapperOptions online;
  /// Keyframes, loop candidates and the pose graph (--loop-closure off: odometry only).
  LoopClosureOptions loops;
  /// A trajectory to compare with (TUM or KITTI): ATE after alignment in the summary.
  std::string reference_file;
  bool help = false;
};

/// --config FILE first (its [--section] and map section), then the flags, which override it.
/// Throws apps::UsageError with a one-line message for unknown options or keys, bad values,
/// or ndtom-map options that give poses (--poses, --passes, ...).
SlamOptions parseSlamOptions(int argc, char** argv);
std::string helpText();

}  // namespace ndtom::slam
