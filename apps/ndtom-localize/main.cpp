// ndtom-localize: the pose of every scan of a log in a saved NDT-OM, by NDT scan-to-map
// registration. Exit code 0 on success, 1 for bad input data or a failed write, 2 for a bad
// command line.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>

#include "localize_options.h"
#include "localize_outputs.h"
#include "map_file.h"
#include "ndtom/map_queries.h"
#include "ndtom_apps/process_clock.h"
#include "ndtom_apps/process_memory.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_apps/trajectory_poses.h"
#include "region_map.h"
#include "tracking.h"

using namespace ndtom::localizer;
using ndtom::apps::InputError;

namespace {

bool hasOccupiedGaussian(const ndtom::NdtMap& map) {
  bool found = false;
  map.forEachCell(
      [&](const ndtom::CellView& c) { found = found || ndtom::isOccupiedGaussian(map, c); });
  return found;
}

int run(const LocalizeOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  ndtom::apps::SourceSettings settings;
  settings.input = o.input;
  settings.format = o.format;
  settings.poses_file = o.poses_file;
  settings.pose_format = o.pose_format;
  settings.decimation = o.decimation;
  settings.max_scans = o.max_scans == 0 ? 0 : o.skip + o.max_scans;
  settings.pose_time_tolerance = o.pose_time_tolerance;
  settings.poses_optional = true;
  auto source = ndtom::apps::openScanSource(settings);
  ndtom::apps::OutputFiles out(o.prefix);

  const auto load_start = std::chrono::steady_clock::now();
  // A tiled map is held in part, around the robot; any other map whole.
  std::optional<RegionMap> region;
  std::optional<ndtom::NdtMap> whole;
  if (isTiledMapFile(o.map_path)) {
    try {
      region.emplace(o.map_path, o.region_radius);
    } catch (const std::exception& e) {
      throw InputError(ndtom::apps::oneLineMessage(e));
    }
    if (region->file().tiles().empty())
      throw InputError(o.map_path + ": the tiled map has no tile to localize in");
  } else {
    whole = loadMapFile(o.map_path);
    if (!hasOccupiedGaussian(*whole))
      throw InputError(o.map_path +
                       ": the map has no occupied cell with a Gaussian to localize in");
  }
  const ndtom::NdtMap& map = region ? region->map() : *whole;
  const double load_seconds = ndtom::apps::secondsSince(load_start);
  if (!o.quiet) std::fprintf(stderr, "ndtom-localize: %s\n", source->description().c_str());

  std::optional<ndtom::apps::TrajectoryPoses> reference;
  if (!o.reference_file.empty())
    reference.emplace(o.reference_file, o.reference_format, o.reference_time_tolerance);
  const ReferenceLookup lookup = [&](size_t index,
                                     double time) -> std::optional<Eigen::Isometry3d> {
    if (!reference) return std::nullopt;
    try {
      return reference->poseFor(index, time);
    } catch (const std::exception&) {  // no pose for this scan: no error for it
      return std::nullopt;
    }
  };

  ndtom::apps::Progress progress(!o.quiet);
  for (size_t k = 0; k < o.skip; ++k)
    if (!source->next())
      throw InputError(o.input + ": fewer than --skip " + std::to_string(o.skip) + " scans");
  TrackingSettings tracking_settings = o.tracking;
  LocalizeSummary::Region region_summary;
  if (region) {
    tracking_settings.prepare_map = [&](const std::optional<Eigen::Vector3d>& around) {
      if (around)
        region->keepAround(*around);
      else
        region->keepEverything();
      region_summary.max_resident_tiles =
          std::max(region_summary.max_resident_tiles, region->residentTiles());
      region_summary.max_resident_bytes =
          std::max(region_summary.max_resident_bytes, map.memoryBytes());
    };
  }
  const TrackingResult tracking =
      track(map, *source, tracking_settings, lookup, progress, o.skip);
  if (tracking.scans.empty()) throw InputError(o.input + ": no scans");
  if (region) {
    region_summary.radius = region->radius();
    region_summary.tiles = region->file().tiles().size();
    region_summary.loads = region->loads();
    region_summary.drops = region->drops();
    if (o.pictures) {  // the picture shows the tiles along the path
      std::vector<Eigen::Vector3d> path;
      for (const ScanRecord& r : tracking.scans)
        if (r.pose) path.push_back(r.pose->translation());
      region->addAlong(path);
    }
  }
  writeTrajectoryOutputs(map, tracking, o, out);

  LocalizeSummary summary;
  summary.options = &o;
  summary.source_description = source->description();
  summary.map_cells = map.numCells();
  if (region) {
    summary.map_cells = 0;
    for (const auto& t : region->file().tiles()) summary.map_cells += t.cells;
    summary.region = region_summary;
  }
  summary.map_gaussians = map.numGaussians();
  summary.map_resolution = map.options().resolution;
  summary.map_load_seconds = load_seconds;
  summary.tracking = &tracking;
  summary.files = out.files();
  summary.files.push_back({"summary", o.prefix + ".summary.json"});
  summary.peak_rss = ndtom::apps::peakRssBytes();
  summary.total_seconds = ndtom::apps::secondsSince(start);
  out.writeBytes("summary", ".summary.json", summaryJson(summary));
  out.commit();
  if (!o.quiet) std::fputs(summaryText(summary).c_str(), stdout);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return ndtom::apps::runProgram("ndtom-localize", [&] {
    const LocalizeOptions options = parseLocalizeOptions(argc, argv);
    if (options.help) {
      std::fputs(helpText().c_str(), stdout);
      return 0;
    }
    return run(options);
  });
}
