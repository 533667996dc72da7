// ndtom-worldgen: a city and a lidar drive through it, written as a folder of scans with
// poses, so that mapping, localization and distributed builds can be tested at the scale of
// kilometres without downloading data. Exit 0 on success, 1 for a failed write, 2 for a bad
// command line.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

#include "city_route.h"
#include "ndtom_internal/atomic_file.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_apps/process_clock.h"
#include "ndtom_apps/progress.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"
#include "simulated_lidar.h"
#include "world_options.h"

namespace {

using namespace ndtom::world;

std::string scanName(size_t i) {
  char name[32];
  std::snprintf(name, sizeof name, "scan%06zu.pcd", i);
  return name;
}

void writeText(const std::string& path, const std::string& text) {
  ndtom::writeFileAtomically(path, text.data(), text.size());
}

int run(const WorldOptions& o) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (!fs::is_directory(o.out)) throw ndtom::apps::UsageError(o.out + ": cannot create the folder");
  const auto start = std::chrono::steady_clock::now();
  const CityWorld city(o.city);
  const auto poses = driveThrough(city, o.route);

  std::string times;
  char line[64];
  for (size_t i = 0; i < poses.size(); ++i) {
    std::snprintf(line, sizeof line, "%.6f\n", double(i) * o.route.step / o.speed);
    times += line;
  }

  // Scans in parallel, each thread taking the next index: files are the same for any count.
  ndtom::apps::Progress progress(!o.quiet);
  progress.start("", poses.size());
  std::atomic<size_t> next{0}, done{0}, points{0};
  std::exception_ptr failure;
  std::mutex report;
  const auto work = [&] {
    for (size_t i; (i = next++) < poses.size();) {
      try {
        const auto scan = simulateScan(city, o.lidar, poses[i], i);
        ndtom::io::writePcdBinary((fs::path(o.out) / scanName(i)).string(), scan);
        points += scan.size();
      } catch (...) {
        std::lock_guard<std::mutex> lock(report);
        if (!failure) failure = std::current_exception();
        next = poses.size();
        return;
      }
      std::lock_guard<std::mutex> lock(report);
      progress.update(++done, points);
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < o.threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
  // Poses last: a folder with poses.txt is complete.
  writeText((fs::path(o.out) / "times.txt").string(), times);
  ndtom::io::writeKittiPoseFile((fs::path(o.out) / "poses.txt").string(), poses);
  if (!o.quiet)
    std::printf("ndtom-worldgen: %zu scans over %.2f km in a city of %dx%d blocks (%zu boxes), "
                "%.1f M points, %.1f s; wrote %s\n",
                poses.size(), o.route.length / 1000, o.city.blocks_x, o.city.blocks_y,
                city.boxes().size(), double(points) / 1e6, ndtom::apps::secondsSince(start),
                o.out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return ndtom::apps::runProgram("ndtom-worldgen", [&] {
    const WorldOptions options = parseWorldOptions(argc, argv);
    if (options.help) {
      std::fputs(worldHelpText().c_str(), stdout);
      return 0;
    }
    return run(options);
  });
}
