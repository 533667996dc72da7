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
#include "ndtom/files/map_io.h"
#include "ndtom/map/map_queries.h"
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

ndtom::apps::SourceSettings sourceSettingsFor(const LocalizeOptions& o) {
  ndtom::apps::SourceSettings settings;
  settings.input = o.input;
  settings.format = o.format;
  settings.poses_file = o.poses_file;
  settings.pose_format = o.pose_format;
  settings.decimation = o.decimation;
  settings.max_scans = o.max_scans == 0 ? 0 : o.skip + o.max_scans;
  settings.pose_time_tolerance = o.pose_time_tolerance;
  settings.poses_optional = true;
  return settings;
}

// The map to localize in: a tiled map held in part, around the robot; any other map whole.
struct LoadedMap {
  std::optional<RegionMap> region;
  std::optional<ndtom::NdtMap> whole;
  double load_seconds = 0;

  const ndtom::NdtMap& map() const { return region ? region->map() : *whole; }
};

void loadMap(const LocalizeOptions& o, LoadedMap& loaded) {
  const auto start = std::chrono::steady_clock::now();
  if (isTiledMapFile(o.map_path)) {
    try {
      loaded.region.emplace(o.map_path, o.region_radius);
    } catch (const std::exception& e) {
      throw InputError(ndtom::apps::oneLineMessage(e));
    }
    if (loaded.region->file().tiles().empty())
      throw InputError(o.map_path + ": the tiled map has no tile to localize in");
  } else {
    loaded.whole = loadMapFile(o.map_path);
    if (!hasOccupiedGaussian(*loaded.whole))
      throw InputError(o.map_path +
                       ": the map has no occupied cell with a Gaussian to localize in");
  }
  loaded.load_seconds = ndtom::apps::secondsSince(start);
}

// The pose of a scan in --reference if it has one (no error for a scan without); none (an
// empty function) without --reference.
ReferenceLookup referenceLookup(const std::optional<ndtom::apps::TrajectoryPoses>& reference) {
  if (!reference) return {};
  return [&reference](size_t index, double time) -> std::optional<Eigen::Isometry3d> {
    try {
      return reference->poseFor(index, time);
    } catch (const std::exception&) {
      return std::nullopt;
    }
  };
}

void skipScans(ndtom::apps::ScanSource& source, const LocalizeOptions& o) {
  for (size_t k = 0; k < o.skip; ++k)
    if (!source.next())
      throw InputError(o.input + ": fewer than --skip " + std::to_string(o.skip) + " scans");
}

// With a tiled map, the resident tiles follow the robot, and the summary counts them.
TrackingSettings trackingSettingsFor(const LocalizeOptions& o, LoadedMap& loaded,
                                     LocalizeSummary::Region& region_summary) {
  TrackingSettings settings = o.tracking;
  if (!loaded.region) return settings;
  settings.prepare_map = [&loaded, &region_summary](const std::optional<Eigen::Vector3d>& around) {
    RegionMap& region = *loaded.region;
    if (around)
      region.keepAround(*around);
    else
      region.keepEverything();
    region_summary.max_resident_tiles =
        std::max(region_summary.max_resident_tiles, region.residentTiles());
    region_summary.max_resident_bytes =
        std::max(region_summary.max_resident_bytes, region.map().memoryBytes());
  };
  return settings;
}

// The tiled map's figures; for the picture, the tiles along the path are loaded.
void finishRegion(const LocalizeOptions& o, const TrackingResult& tracking, RegionMap& region,
                  LocalizeSummary::Region& region_summary) {
  region_summary.radius = region.radius();
  region_summary.tiles = region.file().tiles().size();
  region_summary.loads = region.loads();
  region_summary.drops = region.drops();
  if (!o.pictures) return;
  std::vector<Eigen::Vector3d> path;
  for (const ScanRecord& r : tracking.scans)
    if (r.pose) path.push_back(r.pose->translation());
  region.addAlong(path);
}

// The summary, then every file into place at once.
void writeSummaryAndCommit(const LocalizeOptions& o, const LoadedMap& loaded,
                           const std::string& source_description, const TrackingResult& tracking,
                           const LocalizeSummary::Region& region_summary,
                           std::chrono::steady_clock::time_point start,
                           ndtom::apps::OutputFiles& out) {
  const ndtom::NdtMap& map = loaded.map();
  LocalizeSummary summary;
  summary.options = &o;
  summary.source_description = source_description;
  summary.map_cells = map.numCells();
  if (loaded.region) {
    summary.map_cells = 0;
    for (const auto& t : loaded.region->file().tiles()) summary.map_cells += t.cells;
    summary.region = region_summary;
  }
  summary.map_gaussians = map.numGaussians();
  summary.map_resolution = map.options().resolution;
  summary.map_load_seconds = loaded.load_seconds;
  summary.tracking = &tracking;
  summary.files = out.files();
  summary.files.push_back({"summary", o.prefix + ".summary.json"});
  summary.peak_rss = ndtom::apps::peakRssBytes();
  summary.total_seconds = ndtom::apps::secondsSince(start);
  out.writeBytes("summary", ".summary.json", summaryJson(summary));
  out.commit();
  if (!o.quiet) std::fputs(summaryText(summary).c_str(), stdout);
}

int run(const LocalizeOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  // Open the input and the outputs, load the map: every check that can fail fast.
  auto source = ndtom::apps::openScanSource(sourceSettingsFor(o));
  ndtom::apps::OutputFiles out(o.prefix);
  LoadedMap loaded;
  loadMap(o, loaded);
  if (!o.quiet) std::fprintf(stderr, "ndtom-localize: %s\n", source->description().c_str());
  std::optional<ndtom::apps::TrajectoryPoses> reference;
  if (!o.reference_file.empty())
    reference.emplace(o.reference_file, o.reference_format, o.reference_time_tolerance);

  // Localize the scans.
  ndtom::apps::Progress progress(!o.quiet);
  skipScans(*source, o);
  LocalizeSummary::Region region_summary;
  const TrackingResult tracking =
      track(loaded.map(), *source, trackingSettingsFor(o, loaded, region_summary),
            referenceLookup(reference), progress, o.skip);
  if (tracking.scans.empty()) throw InputError(o.input + ": no scans");
  if (loaded.region) finishRegion(o, tracking, *loaded.region, region_summary);

  // Write the outputs (under temporary names until everything has succeeded).
  writeTrajectoryOutputs(loaded.map(), tracking, o, out);
  if (tracking.extended_map) {
    const std::string path = o.save_map_prefix + ".ndtom";
    try {
      ndtom::saveMap(*tracking.extended_map, path);
    } catch (const std::exception& e) {
      throw InputError("--save-map " + path + ": " + ndtom::apps::oneLineMessage(e));
    }
    if (!o.quiet) std::fprintf(stderr, "ndtom-localize: the extended map: %s\n", path.c_str());
  }
  writeSummaryAndCommit(o, loaded, source->description(), tracking, region_summary, start, out);
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
