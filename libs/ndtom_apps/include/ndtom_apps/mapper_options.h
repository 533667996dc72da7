// The command line of ndtom-map, which ndtom-map-mpi and ndtom-rank-model take as well.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "ndtom_apps/input_format.h"
#include "ndtom_apps/insertion_settings.h"
#include "ndtom_apps/motion_gate.h"
#include "ndtom_io/pose_file.h"
#include "ndtom_io/tum_rgbd.h"

namespace ndtom::mapper {

struct MapperOptions {
  std::string input;
  std::string prefix;  ///< outputs are PREFIX.ndtom, PREFIX.top.png, ...
  apps::InputFormat format = apps::InputFormat::Auto;

  std::string poses_file;  ///< trajectory file; empty: odometry (rawlog) or FOLDER/poses.txt
  ndtom::io::PoseFormat pose_format = ndtom::io::PoseFormat::Auto;
  double pose_time_tolerance = 0.02;  ///< TUM trajectory vs rawlog time stamps (Default: 0.02 s)
  ndtom::io::DepthCamera camera;      ///< TUM RGB-D intrinsics and depth scale
  size_t max_scans = 0;               ///< first N scans; 0 = all
  apps::MotionThresholds motion;      ///< --min-travel, --min-turn (Default: off)

  InsertionSettings insertion;  ///< --config, --section and the .ini keys as options
  int coarse = 0;               ///< also write a map this many times coarser; 0 = none
  int passes = 1;               ///< times the input is replayed into the map (Default: 1)

  bool pictures = true;
  bool octomap = false;  ///< also write PREFIX.bt
  int tile_blocks = 0;   ///< also write PREFIX.ndtomtiles, tiles this many blocks a side; 0 = no
  double resident_budget_mb = 0;  ///< > 0: build out of core, this much map in memory [MB]
  std::string spill_dir;          ///< where the out-of-core build spills; empty: beside PREFIX
  int image_width = 1200;           ///< pixels (Default: 1200)
  uint32_t max_ellipsoids = 50000;  ///< drawn in the 3D picture and scene (Default: 50000)
  int ellipsoid_detail = -1;        ///< their subdivisions, 0-4; -1: by how many are drawn
  bool quiet = false;
  bool help = false;
};

/// Tiles of the out-of-core build when --tiles is not given: 12.8 m at 0.2 m cells, a few
/// MB of city each, so that a budget of tens of MB still holds many of them.
constexpr int kDefaultOutOfCoreTileBlocks = 8;

/// Throws apps::UsageError with a one-line message for unknown options, missing or bad values.
MapperOptions parseMapperOptions(int argc, char** argv);
std::string helpText();

}  // namespace ndtom::mapper
