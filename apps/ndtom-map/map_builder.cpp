#include "map_builder.h"

#include <chrono>
#include <future>

#include "ndtom/map/map_queries.h"
#include "ndtom_apps/budget_message.h"
#include "ndtom_apps/process_clock.h"
#include "ndtom_apps/process_memory.h"

namespace ndtom::mapper {
namespace {

using Clock = std::chrono::steady_clock;

// Adds what `map` holds to `r`.
void countMap(const ndtom::NdtMap& map, PassResult& r) {
  r.cells += map.numCells();
  r.gaussians += map.numGaussians();
  map.forEachCell([&](const ndtom::CellView& c) {
    const ndtom::CellState state = ndtom::cellState(map, c);
    r.occupied += state == ndtom::CellState::Occupied;
    r.free += state == ndtom::CellState::Free;
  });
  r.map_bytes += map.memoryBytes();
}

// Out of core, tile by tile (spilled ones read back one at a time); map_bytes is then the
// sum of the tiles' own maps, what the map would take in memory give or take hash tables.
PassResult describeMap(MappingResult& result) {
  PassResult r;
  if (result.out_of_core)
    result.out_of_core->forEachTile(
        [&](const ndtom::CellIndex&, const ndtom::NdtMap& tile) { countMap(tile, r); });
  else
    countMap(result.map, r);
  r.rss_bytes = apps::currentRssBytes();
  return r;
}

// The scans of a source, the next one read while the current one is inserted when more than
// one thread may run (reading is a tenth of inserting, on a core insertion does not fill).
class ScanReader {
 public:
  ScanReader(apps::ScanSource& source, bool read_ahead) : source_(source), read_ahead_(read_ahead) {
    if (read_ahead_) ahead_ = readAhead();
  }
  ~ScanReader() {
    if (ahead_.valid()) ahead_.wait();  // it uses the source
  }
  std::optional<apps::Scan> next() {
    if (!read_ahead_) return source_.next();
    std::optional<apps::Scan> scan = ahead_.get();
    if (scan) ahead_ = readAhead();
    return scan;
  }

 private:
  std::future<std::optional<apps::Scan>> readAhead() {
    return std::async(std::launch::async, [this] { return source_.next(); });
  }
  apps::ScanSource& source_;
  bool read_ahead_;
  std::future<std::optional<apps::Scan>> ahead_;
};

// One pass: every scan of `source` into `result.map`.
void insertAll(apps::ScanSource& source, const ndtom::ScanOptions& insert,
               const apps::MotionThresholds& motion, bool first_pass, const std::string& input,
               MappingResult& result, apps::Progress& progress) {
  size_t done = 0, points = 0;
  apps::MotionGate gate(motion);
  ScanReader reader(source, insert.threads > 1);
  while (auto scan = reader.next()) {
    // The sensor's position with the frame's orientation: both move rigidly together.
    Eigen::Isometry3d sensor_pose = scan->frame_pose;
    sensor_pose.translation() = scan->sensor_origin;
    if (!gate.accept(sensor_pose)) {
      progress.update(++done, points);
      continue;
    }
    const auto start = Clock::now();
    try {
      result.points +=
          result.out_of_core
              ? result.out_of_core->insertScan(scan->points_world, scan->sensor_origin, insert)
              : result.map.insertScan(scan->points_world, scan->sensor_origin, insert);
    } catch (const std::invalid_argument& e) {  // a bad sensor origin; the map is unchanged
      throw apps::InputError(scan->name + ": " + e.what());
    } catch (const ndtom::MemoryBudgetError& e) {
      throw apps::InputError(scan->name + " in " + input + ": " + apps::budgetMessage(e));
    }
    result.insert_seconds.push_back(apps::secondsSince(start));
    if (first_pass) result.sensor_path.push_back(scan->sensor_origin);
    points += scan->points_world.size();
    progress.update(++done, points);
  }
}

}  // namespace

MappingResult buildMap(std::unique_ptr<apps::ScanSource> source,
                       const apps::SourceSettings& settings, const BuildSettings& build,
                       apps::Progress& progress) {
  MappingResult result;
  result.map = ndtom::NdtMap(build.map);
  result.source_description = source->description();
  if (build.resident_budget > 0)
    result.out_of_core = std::make_unique<ndtom::OutOfCoreMap>(
        build.map, build.resident_budget, build.tile_blocks, build.spill_folder);
  ndtom::ScanOptions insert = build.map.scan;
  insert.threads = build.threads;
  for (int pass = 1; pass <= build.passes; ++pass) {
    if (pass > 1) source = apps::openScanSource(settings);
    const auto start = Clock::now();
    progress.start(
        build.passes > 1 ? "pass " + std::to_string(pass) + "/" + std::to_string(build.passes) : "",
        source->size());
    insertAll(*source, insert, build.motion, pass == 1, settings.input, result, progress);
    progress.finish();
    if (pass == 1) result.skips = source->skips();
    PassResult r = describeMap(result);
    r.scans = source->size();
    r.seconds = apps::secondsSince(start);
    result.passes.push_back(r);
  }
  return result;
}

}  // namespace ndtom::mapper
