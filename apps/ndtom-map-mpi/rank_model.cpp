// ndtom-rank-model: the work of each process of ndtom-map-mpi for N processes, measured in one
// process (each rank's share inserted in turn, CPU time): per-rank balance and the compute
// efficiency T1 / (N * slowest rank) for more processes than this machine has. Communication
// is not part of it (ndtom-map-mpi's .mpi.json has its bytes). Writes PREFIX.rank-model.csv.
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <vector>

#include "mpi_options.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_apps/progress.h"
#include "ndtom_apps/run_program.h"
#include "settings_from_options.h"

using namespace ndtom::mapper;

namespace {

double cpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

struct Share {
  double cpu_s = 0;
  size_t cells = 0, visits = 0;
};

// One rank's part of the map from every scan (ranks == 1 with the serial insertScan).
Share insertShare(const std::vector<Scan>& scans, const ndtom::MapOptions& options,
                  const ndtom::InsertOptions& insert, const ndtom::TileOwnership& owned) {
  ndtom::NdtMap map(options);
  Share s;
  const double start = cpuSeconds();
  for (const Scan& scan : scans) {
    const ndtom::InsertionReport r =
        owned.ranks == 1 ? map.insertScan(scan.points_world, scan.sensor_origin, insert)
                         : map.insertScanPart(scan.points_world, scan.sensor_origin, insert, owned);
    s.visits += r.voxel_visits;
  }
  s.cpu_s = cpuSeconds() - start;
  s.cells = map.numCells();
  return s;
}

int run(int argc, char** argv) {
  std::vector<int64_t> ranks_list{1, 2, 4, 8, 16, 32, 64};
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    if (std::string(argv[i]) == "--ranks" && i + 1 < argc) {
      ranks_list = ndtom::apps::parseIntegerList("--ranks", argv[++i], 1, 4096);
    } else {
      rest.push_back(argv[i]);
    }
  }
  const MpiOptions o = parseMpiOptions(int(rest.size()), rest.data());
  if (o.map.help) {
    std::puts("Usage: ndtom-rank-model INPUT -o PREFIX [--ranks 1,2,4,...] [ndtom-map-mpi options]");
    return 0;
  }
  const InsertionOptions insertion = resolveInsertionOptions(o.map.insertion);
  auto source = openScanSource(sourceSettingsFor(o.map, insertion));
  std::vector<Scan> scans;
  while (auto scan = source->next()) scans.push_back(std::move(*scan));
  const ndtom::MapOptions options = insertion.toMapOptions();
  ndtom::InsertOptions insert = options.insertion;
  insert.threads = 1;  // one core per process

  const Share serial = insertShare(scans, options, insert, {o.rank_tiles, 0, 1});
  std::ofstream csv(o.map.prefix + ".rank-model.csv");
  csv << "ranks,rank,cpu_s,cells,visits\n";
  std::printf("%6s %10s %10s %10s %8s %10s\n", "ranks", "serial_s", "slowest_s", "mean_s",
              "balance", "efficiency");
  ndtom::apps::Progress progress(!o.map.quiet);
  for (const int64_t n : ranks_list) {
    std::vector<Share> shares;
    progress.start(std::to_string(n) + " ranks", size_t(n), "ranks");
    for (int r = 0; r < n; ++r) {
      shares.push_back(n == 1 ? serial : insertShare(scans, options, insert, {o.rank_tiles, r, int(n)}));
      csv << n << ',' << r << ',' << shares.back().cpu_s << ',' << shares.back().cells << ','
          << shares.back().visits << '\n';
      progress.update(size_t(r + 1));
    }
    progress.finish();
    double slowest = 0, sum = 0;
    for (const Share& s : shares) slowest = std::max(slowest, s.cpu_s), sum += s.cpu_s;
    const double mean = sum / double(n);
    std::printf("%6lld %10.3f %10.3f %10.3f %8.3f %10.3f\n", (long long)n, serial.cpu_s, slowest,
                mean, mean / slowest, serial.cpu_s / (double(n) * slowest));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return ndtom::apps::runProgram("ndtom-rank-model", [&] { return run(argc, argv); });
}
