// Everything a run writes besides its summary: the map in the project's format, the MRPT
// map object, a scene for SceneViewer3D, the pictures and the optional coarser map.
#pragma once

#include <optional>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "output_files.h"
#include "run_summary.h"
#include "stage_times.h"

namespace ndtom::mapper {

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
                                             const OutputSettings& settings, OutputFiles& out,
                                             StageTimes& times);

}  // namespace ndtom::mapper
