// Inserting the scans of a source into an NDT-OM, pass after pass, with timing and memory.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "ndtom/map/ndt_map.h"
#include "ndtom/scale/out_of_core_map.h"
#include "ndtom_apps/motion_gate.h"
#include "ndtom_apps/progress.h"
#include "ndtom_apps/scan_source.h"

namespace ndtom::mapper {

/// The map after one pass over the input.
struct PassResult {
  size_t scans = 0;
  size_t cells = 0, gaussians = 0, occupied = 0, free = 0;
  size_t map_bytes = 0;  ///< NdtMap::memoryBytes()
  size_t rss_bytes = 0;  ///< resident set size of the process at the end of the pass
  double seconds = 0;    ///< wall time of the pass (reading + insertion)
};

struct MappingResult {
  ndtom::NdtMap map;                                 ///< empty when built out of core
  std::unique_ptr<ndtom::OutOfCoreMap> out_of_core;  ///< the map, if built out of core
  ndtom::InsertionReport points;       ///< every point of every pass, by what became of it
  std::vector<double> insert_seconds;  ///< per scan, every pass: NdtMap::insertScan only
  std::vector<PassResult> passes;
  std::vector<Eigen::Vector3d> sensor_path;  ///< sensor origins of the first pass
  apps::SourceSkips skips;                   ///< of the first pass
  std::string source_description;
};

struct BuildSettings {
  ndtom::MapOptions map;
  int threads = 1;
  int passes = 1;
  apps::MotionThresholds motion;  ///< the paper's insertion rule; off by default
  uint64_t resident_budget = 0;   ///< > 0: out of core (OutOfCoreMap), this many bytes resident
  int tile_blocks = 0;            ///< out of core: the tiles' edge in blocks
  std::string spill_folder;       ///< out of core: where tiles are spilled
};

/// Inserts every scan of `source` that passes the motion gate (already opened from `settings`),
/// then reopens the input for each further pass. Throws InputError for unreadable data or a bad
/// scan.
MappingResult buildMap(std::unique_ptr<apps::ScanSource> source,
                       const apps::SourceSettings& settings, const BuildSettings& build,
                       apps::Progress& progress);

}  // namespace ndtom::mapper
