// ndtom-map-mpi: ndtom-map with the insertion spread over MPI processes, each owning part of
// space (ndtom/partition/tile_ownership.h) and walking a share of each scan's rays (--ray-share);
// process 0 gathers the map and writes ndtom-map's outputs.
// The map is ndtom-map's bit for bit. Exit code 0 on success, 1 for bad input data or a failed
// write (the other processes are stopped), 2 for a bad command line.
#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <optional>

#include "map_gather.h"
#include "mpi_count_exchange.h"
#include "ndtom/map/memory_budget.h"
#include "ndtom/scale/distributed_insert.h"
#include "ndtom_apps/budget_message.h"
#include "ndtom_apps/height_colors.h"
#include "ndtom_apps/json_writer.h"
#include "ndtom_apps/map_outputs.h"
#include "ndtom_apps/motion_gate.h"
#include "ndtom_apps/mpi_options.h"
#include "ndtom_apps/oblique_view.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_apps/output_files.h"
#include "ndtom_apps/process_clock.h"
#include "ndtom_apps/process_memory.h"
#include "ndtom_apps/progress.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_apps/settings_from_options.h"
#include "ndtom_apps/stage_times.h"
#include "scan_feed.h"

using namespace ndtom::mapper;
namespace apps = ndtom::apps;
using Clock = std::chrono::steady_clock;

namespace {

// What each process did, for the distributed block of the summary.
struct RankFigures {
  double insert_s = 0;  ///< in insertScanPart
  double loop_s = 0;    ///< the scan loop: reading or receiving, and inserting
  double cells = 0;     ///< its part of the map
  double visits = 0;    ///< cells its ray walks visited
  double bytes_sent = 0;
  double bytes_exchanged = 0;  ///< counts sent to other processes (--ray-share rays)
};

// What process 0 reports of the whole run.
struct RunFigures {
  std::vector<RankFigures> ranks;  ///< every process's, in rank order
  size_t scans = 0;
  uint64_t bytes_broadcast = 0;
  double gather_s = 0, total_s = 0;
};

std::string distributedJson(const MpiOptions& o, const RunFigures& run) {
  apps::JsonWriter json;
  json.beginObject();
  json.field("program", "ndtom-map-mpi");
  json.field("ranks", int(run.ranks.size()));
  json.field("scan_input", o.scan_input == ScanInput::Broadcast ? "broadcast" : "each");
  json.field("rank_tiles", o.rank_tiles);
  json.field("ray_share", o.ray_share == RayShare::Rays ? "rays" : "tiles");
  json.field("scans", run.scans);
  json.field("bytes_broadcast", size_t(run.bytes_broadcast));
  json.field("bytes_broadcast_per_scan",
             run.scans ? double(run.bytes_broadcast) / double(run.scans) : 0.0);
  json.field("gather_s", run.gather_s);
  json.field("total_s", run.total_s);
  json.beginArray("per_rank");
  for (const RankFigures& f : run.ranks) {
    json.beginObject();
    json.field("insert_s", f.insert_s);
    json.field("loop_s", f.loop_s);
    json.field("cells", size_t(f.cells));
    json.field("visits", size_t(f.visits));
    json.field("bytes_sent", size_t(f.bytes_sent));
    json.field("bytes_exchanged", size_t(f.bytes_exchanged));
    json.endObject();
  }
  json.endArray();
  json.endObject();
  return json.str();
}

// This process of the distributed build.
struct Process {
  MPI_Comm comm;
  int rank = 0, ranks = 1;
  bool talk = false;  ///< process 0, not --quiet: progress and messages
};

// What this process's scan loop made of the scans.
struct ScanLoop {
  ndtom::NdtMap part;  ///< this process's tiles
  ndtom::InsertionReport points;
  std::vector<Eigen::Vector3d> sensor_path;  ///< of the scans the motion gate let in
  size_t scans = 0;
  RankFigures figures;
};

// One scan into this process's tiles: a share of its rays walked whole, counts traded with the
// other processes (--ray-share rays), or every ray's stretches through its own tiles. Errors
// name the scan: `index` (from 0, in the input's order), its name and the input.
ndtom::InsertionReport insertIntoOwnTiles(ndtom::NdtMap& part, const apps::Scan& scan, size_t index,
                                          const std::string& input,
                                          const ndtom::ScanOptions& insert,
                                          const ndtom::TileOwnership& owned, RayShare share,
                                          MpiCountExchange& exchange) {
  const auto where = [&] {
    return "scan " + std::to_string(index) + " (" + scan.name + ") in " + input + ": ";
  };
  try {
    return share == RayShare::Rays
               ? ndtom::insertScanPart(part, scan.points_world, scan.sensor_origin, insert, owned,
                                       exchange)
               : ndtom::insertScanPart(part, scan.points_world, scan.sensor_origin, insert, owned);
  } catch (const std::invalid_argument& e) {
    throw apps::InputError(where() + e.what());
  } catch (const ndtom::MemoryBudgetError& e) {
    throw apps::InputError(where() + apps::budgetMessage(e));
  } catch (const std::runtime_error& e) {  // another process failed on this scan
    throw apps::InputError(where() + e.what());
  }
}

// Every process inserts every scan the motion gate lets in, into its own tiles.
ScanLoop insertScans(const MpiOptions& mo, const InsertionOptions& insertion, ScanFeed& feed,
                     size_t total, const Process& p) {
  const ndtom::MapOptions map_options = insertion.toMapOptions();
  ndtom::ScanOptions insert = map_options.scan;
  insert.threads = insertion.scan.threads;
  const ndtom::TileOwnership owned{mo.rank_tiles, p.rank, p.ranks};
  ScanLoop loop{ndtom::NdtMap(map_options), {}, {}, 0, {}};
  MpiCountExchange exchange(p.comm);
  apps::MotionGate gate(mo.map.motion);
  apps::Progress progress(p.talk);
  progress.start("", total);
  size_t points_read = 0;
  const auto start = Clock::now();
  while (auto scan = feed.next()) {
    Eigen::Isometry3d sensor_pose = scan->frame_pose;
    sensor_pose.translation() = scan->sensor_origin;
    ++loop.scans;
    points_read += scan->points_world.size();
    if (gate.accept(sensor_pose)) {
      const auto t = Clock::now();
      loop.points += insertIntoOwnTiles(loop.part, *scan, loop.scans - 1, mo.map.input, insert,
                                        owned, mo.ray_share, exchange);
      loop.figures.insert_s += apps::secondsSince(t);
      loop.sensor_path.push_back(scan->sensor_origin);
    }
    progress.update(loop.scans, points_read);
  }
  progress.finish();
  loop.figures.loop_s = apps::secondsSince(start);
  loop.figures.cells = double(loop.part.numCells());
  loop.figures.visits = double(loop.points.voxel_visits);
  loop.figures.bytes_exchanged = double(exchange.bytesSent());
  return loop;
}

// Process 0 gets the whole map (the others an empty one) and every process's figures.
ndtom::NdtMap gatherResults(ScanLoop& loop, const Process& p, RunFigures& run) {
  const auto start = Clock::now();
  uint64_t sent = 0;
  ndtom::NdtMap map = gatherMap(std::move(loop.part), p.comm, sent);
  run.gather_s = apps::secondsSince(start);
  loop.figures.bytes_sent = double(sent);
  run.ranks.resize(static_cast<size_t>(p.ranks));
  static_assert(sizeof(RankFigures) == 6 * sizeof(double));
  MPI_Gather(&loop.figures, 6, MPI_DOUBLE, run.ranks.data(), 6, MPI_DOUBLE, 0, p.comm);
  return map;
}

void printSummary(const RunFigures& run, size_t cells, const apps::OutputFiles& out) {
  double slowest = 0;
  for (const RankFigures& f : run.ranks) slowest = std::max(slowest, f.loop_s);
  std::printf(
      "ndtom-map-mpi: %zu scans on %zu processes: scan loop %.2f s (slowest process), "
      "gather %.2f s, total %.2f s; %zu cells\n",
      run.scans, run.ranks.size(), slowest, run.gather_s, run.total_s, cells);
  for (const apps::WrittenFile& f : out.files()) std::printf("  %s\n", f.path.c_str());
}

// Process 0: ndtom-map's outputs of the gathered map and PREFIX.mpi.json, all put in place at once.
void writeOutputs(const MpiOptions& mo, const InsertionOptions& insertion, ndtom::NdtMap map,
                  const ScanLoop& loop, RunFigures& run, Clock::time_point start,
                  apps::OutputFiles& out) {
  const MapperOptions& o = mo.map;
  if (loop.points.pointsUsed() == 0)
    throw apps::InputError(o.input + ": no usable point in " + std::to_string(loop.scans) +
                           " scans");
  apps::StageTimes times(start);
  times.add("read+insert", loop.figures.loop_s);
  times.add("gather", run.gather_s);
  mrpt_ndtom::CNDTOccupancyMap mrpt_map(insertion.resolution);
  mrpt_map.insertionOptions = insertion;
  mrpt_map.renderOptions =
      apps::renderOptionsFor(map, apps::heightScaleOf(map), o.max_ellipsoids, o.ellipsoid_detail);
  mrpt_map.setNdtMap(std::move(map));
  writeMapOutputs(mrpt_map, loop.sensor_path, outputSettingsFor(o, insertion), out, times);
  run.total_s = apps::secondsSince(start);
  out.writeBytes("distributed", ".mpi.json", distributedJson(mo, run));
  out.commit();
  if (!o.quiet) printSummary(run, mrpt_map.ndtMap().numCells(), out);
}

int run(const MpiOptions& mo, const InsertionOptions& insertion, MPI_Comm comm) {
  const auto start = Clock::now();
  apps::keepFreedHeapForReuse();  // as ndtom-map's in-memory build
  Process p{comm};
  MPI_Comm_rank(comm, &p.rank);
  MPI_Comm_size(comm, &p.ranks);
  p.talk = p.rank == 0 && !mo.map.quiet;
  // Open the input (on every process, or on process 0 to broadcast it) and process 0's outputs.
  std::unique_ptr<apps::ScanSource> source;
  if (mo.scan_input == ScanInput::EachReads || p.rank == 0)
    source = apps::openScanSource(sourceSettingsFor(mo.map, insertion));
  std::optional<apps::OutputFiles> out;
  if (p.rank == 0) out.emplace(mo.map.prefix);
  if (p.talk)
    std::fprintf(stderr, "ndtom-map-mpi: %d processes; %s\n", p.ranks,
                 source->description().c_str());
  const size_t total = source ? source->size() : 0;
  ScanFeed feed(mo.scan_input, std::move(source), comm);

  ScanLoop loop = insertScans(mo, insertion, feed, total, p);
  RunFigures figures;
  figures.scans = loop.scans;
  figures.bytes_broadcast = feed.bytesBroadcast();
  ndtom::NdtMap map = gatherResults(loop, p, figures);
  if (p.rank != 0) return 0;
  writeOutputs(mo, insertion, std::move(map), loop, figures, start, *out);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  // Every process reads the same command line and options file: one message, from process 0.
  std::optional<MpiOptions> options;
  std::optional<InsertionOptions> insertion;
  int status = ndtom::apps::runProgram("ndtom-map-mpi", [&] {
    try {
      options = parseMpiOptions(argc, argv);
      if (options->map.help) {
        if (rank == 0) std::fputs(mpiHelpText().c_str(), stdout);
        return 0;
      }
      insertion = resolveInsertionOptions(options->map.insertion);
    } catch (const ndtom::apps::UsageError&) {
      if (rank == 0) throw;
      return 2;
    }
    return 0;
  });
  if (status == 0 && insertion) {
    status = ndtom::apps::runProgram("ndtom-map-mpi",
                                     [&] { return run(*options, *insertion, MPI_COMM_WORLD); });
    // A process that failed stops the others, which would wait for it forever.
    if (status != 0 && ranks > 1) MPI_Abort(MPI_COMM_WORLD, status);
  }
  MPI_Finalize();
  return status;
}
