// What ndtom-localize writes: the trajectory (TUM format), the summary (JSON) and a picture
// of the path on the map seen from above; and the short text for the terminal.
#pragma once

#include <optional>
#include <string>

#include "localize_options.h"
#include "ndtom/map/ndt_map.h"
#include "ndtom_apps/output_files.h"
#include "tracking.h"

namespace ndtom::localizer {

/// "t x y z qx qy qz qw" per scan, the kept pose (map frame), as TUM's tools read it.
std::string trajectoryTum(const TrackingResult& tracking);

/// One CSV row per scan: index, outcome, what found it, pose, error, verdict figures, time.
std::string scansCsv(const TrackingResult& tracking);

struct LocalizeSummary {
  const LocalizeOptions* options = nullptr;
  std::string source_description;
  size_t map_cells = 0, map_gaussians = 0;
  double map_resolution = 0;
  double map_load_seconds = 0;
  /// A tiled map, held in part around the robot.
  struct Region {
    double radius = 0;
    size_t tiles = 0, loads = 0, drops = 0;
    size_t max_resident_tiles = 0, max_resident_bytes = 0;
  };
  std::optional<Region> region;
  const TrackingResult* tracking = nullptr;
  double total_seconds = 0;
  size_t peak_rss = 0;
  std::vector<apps::WrittenFile> files;
};

std::string summaryJson(const LocalizeSummary& summary);
std::string summaryText(const LocalizeSummary& summary);

/// Stages PREFIX.tum, PREFIX.scans.csv and, if asked, PREFIX.top.png in `out`.
void writeTrajectoryOutputs(const ndtom::NdtMap& map, const TrackingResult& tracking,
                            const LocalizeOptions& options, apps::OutputFiles& out);

}  // namespace ndtom::localizer
