// ndtom-map: builds an NDT Occupancy Map from scans with known poses (MRPT rawlog or
// simplemap, TUM RGB-D sequence, PCD folder) and writes the map, an MRPT map object, a 3D
// scene, pictures and a summary. Exit code 0 on success, 1 for bad input data or a failed
// write, 2 for a bad command line.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "map_builder.h"
#include "ndtom_apps/map_outputs.h"
#include "ndtom_apps/mapper_options.h"
#include "ndtom_apps/oblique_view.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_apps/process_clock.h"
#include "ndtom_apps/process_memory.h"
#include "ndtom_apps/run_budget.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_apps/scan_source.h"
#include "ndtom_apps/settings_from_options.h"
#include "run_summary.h"
#include "spill_folder.h"

using namespace ndtom::mapper;
namespace apps = ndtom::apps;

namespace {

void requireSomePoints(const MappingResult& mapping, const std::string& input) {
  if (mapping.points.pointsUsed() > 0) return;
  throw apps::InputError(input + ": no usable point in " + std::to_string(mapping.passes[0].scans) +
                         " scans (" + std::to_string(mapping.points.points_in) + " points read, " +
                         std::to_string(mapping.points.rejected()) +
                         " rejected: see --min-range, --max-range)");
}

RunSummary summarize(const MapperOptions& o, const apps::SourceSettings& settings,
                     const ndtom::MapOptions& map_options, int threads,
                     const MappingResult& mapping, const std::optional<CoarseMapInfo>& coarse,
                     std::chrono::steady_clock::time_point start) {
  RunSummary summary;
  summary.input = o.input;
  summary.format = apps::inputFormatName(settings.format);
  summary.map_options = map_options;
  summary.threads = threads;
  summary.mapping = &mapping;
  summary.coarse = coarse;
  summary.peak_rss = ndtom::apps::peakRssBytes();
  summary.total_seconds = apps::secondsSince(start);
  return summary;
}

// Command-line values that only make sense together, checked before any scan is read.
void checkOptionsTogether(const MapperOptions& o, const InsertionOptions& insertion) {
  if (o.coarse >= 2 && !(insertion.resolution * o.coarse <= ndtom::kMaxResolution)) {
    char why[160];
    std::snprintf(why, sizeof(why),
                  ": the coarse map's cells would be %g m (--resolution %g), over the largest "
                  "resolution, %g m",
                  insertion.resolution * o.coarse, insertion.resolution, ndtom::kMaxResolution);
    throw ndtom::apps::UsageError("--coarse " + std::to_string(o.coarse) + why);
  }
}

// The summary, then every file into place at once.
void writeSummaryAndCommit(const MapperOptions& o, RunSummary& summary, apps::StageTimes& times,
                           apps::OutputFiles& out) {
  summary.stages = &times;
  summary.files = out.files();
  summary.files.push_back({"summary", o.prefix + ".summary.json"});
  out.writeBytes("summary", ".summary.json", summaryJson(summary));
  out.commit();
  if (!o.quiet) std::fputs(summaryText(summary).c_str(), stdout);
}

// Out of core: the tiled file, written tile by tile, and the summary; nothing needs the whole
// map in memory.
void writeOutOfCore(const MapperOptions& o, const apps::SourceSettings& settings,
                    const BuildSettings& build, const MappingResult& mapping,
                    apps::OutputFiles& out, apps::StageTimes& times,
                    std::chrono::steady_clock::time_point start, size_t peak_rss_after_mapping,
                    const RunBudget& budget) {
  const std::string tiles_file = out.stage("tiled_map", ".ndtomtiles");
  times.time("tiled_map", [&] { mapping.out_of_core->saveTiled(tiles_file); });
  RunSummary summary = summarize(o, settings, build.map, build.threads, mapping, {}, start);
  summary.budget = budget;
  summary.peak_rss_after_mapping = peak_rss_after_mapping;
  summary.out_of_core =
      OutOfCoreInfo{build.resident_budget, build.tile_blocks, mapping.out_of_core->stats()};
  writeSummaryAndCommit(o, summary, times, out);
}

int run(const MapperOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  // Read the options and open the input: every check that can fail fast happens here.
  InsertionOptions insertion = resolveInsertionOptions(o.insertion);
  const RunBudget budget = applyRunBudget(insertion, o.insertion, o.input);
  checkOptionsTogether(o, insertion);
  const apps::SourceSettings settings = sourceSettingsFor(o, insertion);
  auto source = apps::openScanSource(settings);
  apps::OutputFiles out(o.prefix);
  if (!o.quiet) std::fprintf(stderr, "ndtom-map: %s\n", source->description().c_str());
  BuildSettings build;
  build.map = insertion.toMapOptions();
  build.threads = insertion.scan.threads;
  build.passes = o.passes;
  build.motion = o.motion;
  std::optional<SpillFolder> spill;
  double resident_budget_mb = o.resident_budget_mb;
  if (resident_budget_mb <= 0 && needsOutOfCore(budget) && o.coarse < 2 && !o.octomap) {
    resident_budget_mb = double(budget.bytes) / 2 / 1e6;
    if (!o.quiet)
      std::fprintf(stderr,
                   "ndtom-map: the input (%.0f MB) would make a map of about its size, and 4 x "
                   "that is more than half of the %.0f MB available: building out of core "
                   "(--memory-budget builds in memory anyway)\n",
                   double(budget.input_bytes) / 1e6, double(budget.available_bytes) / 1e6);
  }
  // An in-memory build reuses its scan buffers (-5 % wall, 40 % fewer page faults on the
  // lidar scans); one under a budget gives what it frees back.
  if (resident_budget_mb <= 0) {
    ndtom::apps::keepFreedHeapForReuse();
  } else {
    spill.emplace(o.prefix, o.spill_dir);
    build.resident_budget = uint64_t(std::round(resident_budget_mb * 1e6));
    build.tile_blocks = o.tile_blocks > 0 ? o.tile_blocks : kDefaultOutOfCoreTileBlocks;
    build.spill_folder = spill->path();
    if (!o.quiet)
      std::fprintf(stderr,
                   "ndtom-map: out of core, %g MB resident, tiles of %d blocks spilled to %s; "
                   "writes %s.ndtomtiles and the summary only (no single-file map, MRPT map, "
                   "scene or pictures: they need the whole map in memory)\n",
                   resident_budget_mb, build.tile_blocks, spill->path().c_str(),
                   o.prefix.c_str());
  }

  // Insert the scans.
  ndtom::apps::Progress progress(!o.quiet);
  MappingResult mapping = buildMap(std::move(source), settings, build, progress);
  requireSomePoints(mapping, o.input);
  const size_t peak_rss_after_mapping = ndtom::apps::peakRssBytes();
  apps::StageTimes times(start);
  double passes_s = 0, insert_s = 0;
  for (const PassResult& p : mapping.passes) passes_s += p.seconds;
  for (const double s : mapping.insert_seconds) insert_s += s;
  times.add("read", passes_s - insert_s);  // reading, decoding and moving the scans
  times.add("insert", insert_s);

  if (mapping.out_of_core) {
    writeOutOfCore(o, settings, build, mapping, out, times, start, peak_rss_after_mapping, budget);
    return 0;
  }

  // Write the outputs (under temporary names until everything has succeeded).
  mrpt_ndtom::CNDTOccupancyMap map(insertion.resolution);
  map.insertionOptions = insertion;
  map.renderOptions = apps::renderOptionsFor(mapping.map, apps::heightScaleOf(mapping.map),
                                             o.max_ellipsoids, o.ellipsoid_detail);
  if (!o.quiet && o.ellipsoid_detail > int(map.renderOptions.subdivisions))
    std::fprintf(
        stderr,
        "ndtom-map: --ellipsoid-detail %d lowered to %u: the scene holds at most %zu triangles\n",
        o.ellipsoid_detail, map.renderOptions.subdivisions, mrpt_ndtom::kMaxSceneTriangles);
  map.setNdtMap(std::move(mapping.map));
  const OutputSettings output_settings = outputSettingsFor(o, insertion);
  const auto coarse = writeMapOutputs(map, mapping.sensor_path, output_settings, out, times);

  // The summary, then every file into place at once.
  RunSummary summary = summarize(o, settings, map.ndtMap().options(),
                                 map.insertionOptions.scan.threads, mapping, coarse, start);
  summary.budget = budget;
  summary.peak_rss_after_mapping = peak_rss_after_mapping;
  writeSummaryAndCommit(o, summary, times, out);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return ndtom::apps::runProgram("ndtom-map", [&] {
    const MapperOptions options = parseMapperOptions(argc, argv);
    if (options.help) {
      std::fputs(helpText().c_str(), stdout);
      return 0;
    }
    return run(options);
  });
}
