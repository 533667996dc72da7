// ndtom-rank-model: the work of each process of ndtom-map-mpi for N processes, measured in one
// process (CPU time): per-rank balance and the compute efficiency T1 / (N * slowest rank) for
// more processes than this machine has. With --ray-share tiles each rank's share is inserted in
// turn; with --ray-share rays the ranks run as threads trading counts through memory (each
// thread's own CPU time), and the bytes each sends are counted. Network time is not part of
// it. Writes PREFIX.rank-model.csv.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <thread>
#include <vector>

#include "ndtom/scale/distributed_insert.h"
#include "ndtom_internal/thread_count_exchange.h"
#include "ndtom_apps/csv_table.h"
#include "ndtom_apps/mpi_options.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_apps/output_files.h"
#include "ndtom_apps/process_clock.h"
#include "ndtom_apps/progress.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_apps/settings_from_options.h"

using namespace ndtom::mapper;
namespace apps = ndtom::apps;

namespace {

struct Share {
  double cpu_s = 0;
  size_t cells = 0, visits = 0;
  size_t bytes_sent = 0;  ///< counts for other ranks (--ray-share rays)
};

// A rank's port to the others, counting what it sends.
class CountedPort : public ndtom::CountExchange {
 public:
  explicit CountedPort(ndtom::CountExchange& port) : port_(port) {}
  bool exchange(bool failed, const std::vector<std::vector<uint32_t>>& outgoing,
                std::vector<std::vector<uint32_t>>& incoming) override {
    for (const auto& words : outgoing) bytes_ += words.size() * sizeof(uint32_t);
    return port_.exchange(failed, outgoing, incoming);
  }
  size_t bytes() const { return bytes_; }

 private:
  ndtom::CountExchange& port_;
  size_t bytes_ = 0;
};

// Every rank's part of the map from every scan, the ranks sharing the rays out: one thread
// each, as they must trade counts scan by scan.
std::vector<Share> insertSharedRays(const std::vector<apps::Scan>& scans,
                                    const ndtom::MapOptions& options,
                                    const ndtom::ScanOptions& insert, int rank_tiles, int ranks) {
  ndtom::ThreadCountExchange hub(ranks);
  std::vector<Share> shares(static_cast<size_t>(ranks));
  std::vector<std::exception_ptr> errors(static_cast<size_t>(ranks));
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
    threads.emplace_back([&, r] {
      try {
        const ndtom::TileOwnership owned{rank_tiles, r, ranks};
        CountedPort port(hub.port(r));
        ndtom::NdtMap map(options);
        Share& s = shares[size_t(r)];
        const double start = apps::threadCpuSeconds();
        for (const apps::Scan& scan : scans)
          s.visits += ndtom::insertScanPart(map, scan.points_world, scan.sensor_origin, insert, owned, port)
                          .voxel_visits;
        s.cpu_s = apps::threadCpuSeconds() - start;
        s.cells = map.numCells();
        s.bytes_sent = port.bytes();
      } catch (...) {
        errors[size_t(r)] = std::current_exception();
      }
    });
  for (std::thread& t : threads) t.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  return shares;
}

// One rank's part of the map from every scan (ranks == 1 with the serial insertScan).
Share insertShare(const std::vector<apps::Scan>& scans, const ndtom::MapOptions& options,
                  const ndtom::ScanOptions& insert, const ndtom::TileOwnership& owned) {
  ndtom::NdtMap map(options);
  Share s;
  const double start = apps::processCpuSeconds();
  for (const apps::Scan& scan : scans) {
    const ndtom::InsertionReport r =
        owned.ranks == 1 ? map.insertScan(scan.points_world, scan.sensor_origin, insert)
                         : ndtom::insertScanPart(map, scan.points_world, scan.sensor_origin, insert, owned);
    s.visits += r.voxel_visits;
  }
  s.cpu_s = apps::processCpuSeconds() - start;
  s.cells = map.numCells();
  return s;
}

struct RankModelOptions {
  MpiOptions mpi;
  std::vector<int64_t> ranks{1, 2, 4, 8, 16, 32, 64};
};

// --ranks, then ndtom-map-mpi's options.
RankModelOptions parseRankModelOptions(int argc, char** argv) {
  RankModelOptions o;
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    if (std::string(argv[i]) == "--ranks" && i + 1 < argc) {
      o.ranks = apps::parseIntegerList("--ranks", argv[++i], 1, 4096);
    } else {
      rest.push_back(argv[i]);
    }
  }
  o.mpi = parseMpiOptions(int(rest.size()), rest.data());
  return o;
}

std::vector<apps::Scan> readAllScans(const MapperOptions& o, const InsertionOptions& insertion) {
  auto source = apps::openScanSource(sourceSettingsFor(o, insertion));
  std::vector<apps::Scan> scans;
  while (auto scan = source->next()) scans.push_back(std::move(*scan));
  return scans;
}

// Every rank's share for `ranks` processes, the serial run standing for one.
std::vector<Share> sharesOf(int ranks, const Share& serial, const std::vector<apps::Scan>& scans,
                            const ndtom::MapOptions& options, const ndtom::ScanOptions& insert,
                            const MpiOptions& o, apps::Progress& progress) {
  if (ranks == 1) return {serial};
  if (o.ray_share == RayShare::Rays)
    return insertSharedRays(scans, options, insert, o.rank_tiles, ranks);
  std::vector<Share> shares;
  for (int r = 0; r < ranks; ++r) {
    shares.push_back(insertShare(scans, options, insert, {o.rank_tiles, r, ranks}));
    progress.update(size_t(r + 1));
  }
  return shares;
}

// One line of the table on stdout: the slowest and mean rank against the serial run.
void printRanks(int ranks, const Share& serial, const std::vector<Share>& shares, size_t scans,
                bool share_rays) {
  double slowest = 0, sum = 0, bytes = 0;
  for (const Share& s : shares)
    slowest = std::max(slowest, s.cpu_s), sum += s.cpu_s, bytes += double(s.bytes_sent);
  const double mean = sum / double(ranks);
  std::printf("%6d %10.3f %10.3f %10.3f %8.3f %10.3f", ranks, serial.cpu_s, slowest, mean,
              mean / slowest, serial.cpu_s / (double(ranks) * slowest));
  if (share_rays)
    std::printf("  %18.3f", scans == 0 ? 0.0 : bytes / double(ranks) / double(scans) / 1e6);
  std::printf("\n");
}

int run(int argc, char** argv) {
  const RankModelOptions ro = parseRankModelOptions(argc, argv);
  const MpiOptions& o = ro.mpi;
  if (o.map.help) {
    std::puts("Usage: ndtom-rank-model INPUT -o PREFIX [--ranks 1,2,4,...] [ndtom-map-mpi options]");
    return 0;
  }
  const InsertionOptions insertion = resolveInsertionOptions(o.map.insertion);
  apps::OutputFiles out(o.map.prefix);  // its folder made now, not after the work
  const std::vector<apps::Scan> scans = readAllScans(o.map, insertion);
  const ndtom::MapOptions options = insertion.toMapOptions();
  ndtom::ScanOptions insert = options.scan;
  insert.threads = 1;  // one core per process

  const Share serial = insertShare(scans, options, insert, {o.rank_tiles, 0, 1});
  const bool share_rays = o.ray_share == RayShare::Rays;
  std::printf("%6s %10s %10s %10s %8s %10s%s\n", "ranks", "serial_s", "slowest_s", "mean_s",
              "balance", "efficiency", share_rays ? "  MB_sent/scan/rank" : "");
  apps::CsvTable csv({"ranks", "rank", "cpu_s", "cells", "visits", "bytes_sent"});
  apps::Progress progress(!o.map.quiet);
  for (const int64_t n : ro.ranks) {
    progress.start(std::to_string(n) + " ranks", size_t(n), "ranks");
    const std::vector<Share> shares = sharesOf(int(n), serial, scans, options, insert, o, progress);
    progress.finish();
    for (size_t r = 0; r < shares.size(); ++r)
      csv.addRow({n, r, apps::CsvCell::formatted("%g", shares[r].cpu_s), shares[r].cells,
                  shares[r].visits, shares[r].bytes_sent});
    printRanks(int(n), serial, shares, scans.size(), share_rays);
  }
  out.writeBytes("rank_model", ".rank-model.csv", csv.text());
  out.commit();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return ndtom::apps::runProgram("ndtom-rank-model", [&] { return run(argc, argv); });
}
