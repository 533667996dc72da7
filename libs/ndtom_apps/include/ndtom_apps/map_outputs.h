// Everything a run writes besides its summary: the map in the project's format, the MRPT
// map object, a scene for SceneViewer3D, the pictures and the optional coarser map.
#pragma once

#include <optional>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom_apps/output_files.h"
#include "ndtom_apps/stage_times.h"

namespace ndtom::mapper {

/// The coarser map written beside the map (--coarse), for the summary.
struct CoarseMapInfo {
  int factor = 0;
  double resolution = 0;  ///< m
  size_t cells = 0, gaussians = 0;
};

struct OutputSettings {
  int coarse = 0;  ///< 0: no coarse map
  bool pictures = true;
  int image_width = 1200;
  uint32_t max_ellipsoids = 50000;
  bool octomap = false;  ///< also PREFIX.bt
  int threads = 1;  ///< above 1, the scene is written beside the other outputs
  int tile_blocks = 0;  ///< also PREFIX.ndtomtiles (tiles this many blocks a side) if > 0
};

/// Stages every output in `out` (nothing is committed here), in this order:
///   .ndtom          ndtom::encodeMap of the map
///   .ndtommap       the CNDTOccupancyMap in an MRPT archive (CSerializable)
///   .3Dscene        ellipsoids and sensor path, for SceneViewer3D
///   .top.png, .3d.png   the pictures (unless disabled)
///   .coarseK.ndtom  the map K times coarser (if asked)
///   .bt             the map as an OctoMap (if asked)
///   .ndtomtiles     the map in tiles (if asked)
/// Returns the coarse map's counts if one was written; adds each output's time to `times`.
std::optional<CoarseMapInfo> writeMapOutputs(const mrpt_ndtom::CNDTOccupancyMap& map,
                                             const std::vector<Eigen::Vector3d>& sensor_path,
                                             const OutputSettings& settings, apps::OutputFiles& out,
                                             apps::StageTimes& times);

}  // namespace ndtom::mapper
