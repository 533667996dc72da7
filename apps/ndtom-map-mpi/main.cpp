// ndtom-map-mpi: ndtom-map with the insertion spread over MPI processes, each owning part of
// space (ndtom/tile_ownership.h) and walking a share of each scan's rays (--ray-share);
// process 0 gathers the map and writes ndtom-map's outputs.
// The map is ndtom-map's bit for bit. Exit code 0 on success, 1 for bad input data or a failed
// write (the other processes are stopped), 2 for a bad command line.
#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <optional>

#include "map_gather.h"
#include "mpi_count_exchange.h"
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

std::string distributedJson(const MpiOptions& o, int ranks, const std::vector<RankFigures>& r,
                            uint64_t bytes_broadcast, size_t scans, double gather_s,
                            double total_s) {
  apps::JsonWriter json;
  json.beginObject();
  json.field("program", "ndtom-map-mpi");
  json.field("ranks", ranks);
  json.field("scan_input", o.scan_input == ScanInput::Broadcast ? "broadcast" : "each");
  json.field("rank_tiles", o.rank_tiles);
  json.field("ray_share", o.ray_share == RayShare::Rays ? "rays" : "tiles");
  json.field("scans", scans);
  json.field("bytes_broadcast", size_t(bytes_broadcast));
  json.field("bytes_broadcast_per_scan", scans ? double(bytes_broadcast) / double(scans) : 0.0);
  json.field("gather_s", gather_s);
  json.field("total_s", total_s);
  json.beginArray("per_rank");
  for (const RankFigures& f : r) {
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

int run(const MpiOptions& mo, const InsertionOptions& insertion, MPI_Comm comm) {
  const auto start = Clock::now();
  ndtom::apps::keepFreedHeapForReuse();  // as ndtom-map's in-memory build
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const MapperOptions& o = mo.map;
  const apps::SourceSettings settings = sourceSettingsFor(o, insertion);
  std::unique_ptr<apps::ScanSource> source;
  if (mo.scan_input == ScanInput::EachReads || rank == 0) source = apps::openScanSource(settings);
  std::optional<apps::OutputFiles> out;
  if (rank == 0) out.emplace(o.prefix);
  const bool talk = rank == 0 && !o.quiet;
  if (talk)
    std::fprintf(stderr, "ndtom-map-mpi: %d processes; %s\n", ranks,
                 source->description().c_str());
  const size_t total = source ? source->size() : 0;
  ScanFeed feed(mo.scan_input, std::move(source), comm);

  // Every process inserts every scan, into its own tiles.
  const ndtom::MapOptions map_options = insertion.toMapOptions();
  ndtom::InsertOptions insert = map_options.insertion;
  insert.threads = insertion.insertion.threads;
  const ndtom::TileOwnership owned{mo.rank_tiles, rank, ranks};
  ndtom::NdtMap part(map_options);
  MpiCountExchange exchange(comm);
  ndtom::apps::MotionGate gate(o.motion);
  ndtom::apps::Progress progress(talk);
  progress.start("", total);
  ndtom::InsertionReport points;
  std::vector<Eigen::Vector3d> sensor_path;
  RankFigures mine;
  size_t done = 0, points_read = 0;
  const auto loop_start = Clock::now();
  while (auto scan = feed.next()) {
    Eigen::Isometry3d sensor_pose = scan->frame_pose;
    sensor_pose.translation() = scan->sensor_origin;
    ++done;
    points_read += scan->points_world.size();
    if (gate.accept(sensor_pose)) {
      const auto t = Clock::now();
      try {
        points += mo.ray_share == RayShare::Rays
                      ? part.insertScanPart(scan->points_world, scan->sensor_origin, insert, owned,
                                            exchange)
                      : part.insertScanPart(scan->points_world, scan->sensor_origin, insert, owned);
      } catch (const std::invalid_argument& e) {
        throw apps::InputError(scan->name + ": " + e.what());
      }
      mine.insert_s += apps::secondsSince(t);
      sensor_path.push_back(scan->sensor_origin);
    }
    progress.update(done, points_read);
  }
  progress.finish();
  mine.loop_s = apps::secondsSince(loop_start);
  mine.cells = double(part.numCells());
  mine.visits = double(points.voxel_visits);
  mine.bytes_exchanged = double(exchange.bytesSent());

  const auto gather_start = Clock::now();
  uint64_t sent = 0;
  ndtom::NdtMap map = gatherMap(std::move(part), comm, sent);
  const double gather_s = apps::secondsSince(gather_start);
  mine.bytes_sent = double(sent);
  std::vector<RankFigures> all(static_cast<size_t>(ranks));
  static_assert(sizeof(RankFigures) == 6 * sizeof(double));
  MPI_Gather(&mine, 6, MPI_DOUBLE, all.data(), 6, MPI_DOUBLE, 0, comm);
  if (rank != 0) return 0;

  if (points.pointsUsed() == 0)
    throw apps::InputError(o.input + ": no usable point in " + std::to_string(done) + " scans");
  apps::StageTimes times(start);
  times.add("read+insert", mine.loop_s);
  times.add("gather", gather_s);
  mrpt_ndtom::CNDTOccupancyMap mrpt_map(insertion.resolution);
  mrpt_map.insertionOptions = insertion;
  mrpt_map.renderOptions =
      apps::renderOptionsFor(map, apps::heightScaleOf(map), o.max_ellipsoids, o.ellipsoid_detail);
  mrpt_map.setNdtMap(std::move(map));
  const OutputSettings output_settings = outputSettingsFor(o, insertion);
  writeMapOutputs(mrpt_map, sensor_path, output_settings, *out, times);
  const double total_s = apps::secondsSince(start);
  out->writeBytes("distributed", ".mpi.json",
                  distributedJson(mo, ranks, all, feed.bytesBroadcast(), done, gather_s, total_s));
  out->commit();
  if (!o.quiet) {
    double slowest = 0;
    for (const RankFigures& f : all) slowest = std::max(slowest, f.loop_s);
    std::printf("ndtom-map-mpi: %zu scans on %d processes: scan loop %.2f s (slowest process), "
                "gather %.2f s, total %.2f s; %zu cells\n",
                done, ranks, slowest, gather_s, total_s, mrpt_map.ndtMap().numCells());
    for (const apps::WrittenFile& f : out->files()) std::printf("  %s\n", f.path.c_str());
  }
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
