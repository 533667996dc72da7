// ndtom-bench: replays the same scans into NDT-OM (both ray modes, one and more threads),
// OctoMap and MRPT's COccupancyGridMap3D in one process, and reports times, rates, memory,
// cell counts, ratios measured in this run, and the project's targets. See --help.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <stdexcept>

#include "bench_options.h"
#include "bench_runner.h"
#include "map_comparison.h"
#include "mrpt_grid_system.h"
#include "ndtom_apps/machine_info.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_system.h"
#include "octomap_system.h"
#include "real_time.h"
#include "registration_run.h"
#include "report.h"
#include "scaling.h"
#include "synthetic_scans.h"
#include "targets.h"
#include "time_plot.h"

using namespace ndtom;
using namespace ndtom::bench;

namespace {

constexpr int kDefaultSyntheticScans = 60;
constexpr double kMaxGridBytes = 8e9;  // the dense grid is refused beyond this
// A side-by-side replay at a coarse resolution lasts under a second, and one spell of load
// from another tenant of the host would decide it: pool at least this many replays, and at
// least this long on the multi-thread side (with 2.5 s, eight runs of one build gave 1.58-1.88x
// per resolution around a median of 1.77x).
constexpr int kMinPairedRepeats = 3;
constexpr double kMinPairedSeconds = 6;

/// One system to run: a kind, and the thread count for NDT-OM.
struct PlannedRun {
  SystemKind kind;
  int threads;
};

std::vector<PlannedRun> planRuns(const BenchOptions& o, const std::vector<int>& threads) {
  std::vector<PlannedRun> plan;
  for (SystemKind kind : o.systems) {
    if (!isNdtom(kind)) {
      plan.push_back({kind, 1});
      continue;
    }
    for (int t : threads) plan.push_back({kind, t});
  }
  return plan;
}

std::unique_ptr<MappingSystem> makeSystem(const PlannedRun& run, double resolution,
                                          double max_range, const Box& bounds) {
  switch (run.kind) {
    case SystemKind::NdtomPerPoint:
      return std::make_unique<NdtomSystem>(resolution, max_range, RayMode::PerPoint, run.threads);
    case SystemKind::NdtomPerHitCell:
      return std::make_unique<NdtomSystem>(resolution, max_range, RayMode::PerHitCell, run.threads);
    case SystemKind::Octomap:
      return std::make_unique<OctomapSystem>(resolution, max_range);
    case SystemKind::MrptGrid3d:
      return std::make_unique<MrptGridSystem>(resolution, max_range, bounds);
  }
  throw std::logic_error("unknown system");
}

/// Fills vs_exact / vs_one_thread of the NDT-OM speed-ups of one dataset and resolution.
void compareNdtomMaps(std::vector<RunResult>& runs, size_t first,
                      const std::map<std::string, std::unique_ptr<NdtMap>>& maps) {
  const auto find = [&](const std::string& label) {
    const auto it = maps.find(label);
    return it == maps.end() ? nullptr : it->second.get();
  };
  const NdtMap* exact = find("ndtom-point/t1");
  for (size_t i = first; i < runs.size(); ++i) {
    RunResult& r = runs[i];
    const NdtMap* map = find(r.label);
    if (!map) continue;
    if (exact && r.label != "ndtom-point/t1")
      r.vs_exact = compareMaps("ndtom-point/t1", *exact, *map);
    const std::string one = r.label.substr(0, r.label.find('/')) + "/t1";
    if (r.threads > 1)
      if (const NdtMap* single = find(one)) r.vs_one_thread = compareMaps(one, *single, *map);
  }
}

void checkGridSize(const BenchOptions& o, const ScanSet& set, const Box& bounds) {
  for (SystemKind kind : o.systems) {
    if (kind != SystemKind::MrptGrid3d) continue;
    const double r = *std::min_element(o.resolutions.begin(), o.resolutions.end());
    const Eigen::Vector3d extent = (bounds.max - bounds.min).array() / r + 3;
    const double bytes = extent.prod();
    if (bytes > kMaxGridBytes)
      throw std::runtime_error("mrpt-grid3d at " + std::to_string(r) + " m needs a " +
                               std::to_string(bytes / 1e9) + " GB dense grid for " + set.name +
                               "; use a coarser resolution or leave it out of --systems");
  }
}

/// Registration against the map of ndtom-point/t1 (else the first NDT-OM map) at each thread
/// count; a multi-thread run's poses are compared with one thread's.
void runRegistrations(const ScanSet& set, const BenchOptions& o, const std::vector<int>& threads,
                      const std::map<std::string, std::unique_ptr<NdtMap>>& maps,
                      apps::Progress& progress, int& run_index, int total_runs,
                      std::vector<RunResult>& registrations) {
  if (o.registration_scans <= 0 || maps.empty()) return;
  const auto exact = maps.find("ndtom-point/t1");
  const NdtMap& map = *(exact != maps.end() ? exact : maps.begin())->second;
  const size_t scans = std::min(size_t(o.registration_scans), set.scans.size());
  std::vector<Eigen::Isometry3d> one_thread_poses;
  for (const int t : threads) {
    char title[200];
    std::snprintf(title, sizeof title, "run %d/%d %s %.2f m registration on %d thread(s)",
                  ++run_index, total_runs, set.name.c_str(), map.options().resolution, t);
    progress.start(title, scans);
    std::vector<Eigen::Isometry3d> poses;
    RunResult pyramid;
    RunResult r = runRegistration(map, set, scans, t, progress, poses, pyramid);
    if (t == 1) {
      one_thread_poses = poses;
    } else if (!one_thread_poses.empty()) {
      bool same = poses.size() == one_thread_poses.size();
      for (size_t i = 0; same && i < poses.size(); ++i)
        same = poses[i].matrix() == one_thread_poses[i].matrix();
      r.same_poses_as_t1 = same;
    }
    registrations.push_back(std::move(r));
    if (!pyramid.scan_seconds.empty()) registrations.push_back(std::move(pyramid));
  }
}

void runDataset(const ScanSet& set, const BenchOptions& o, const std::vector<PlannedRun>& plan,
                const std::vector<int>& threads, apps::Progress& progress, int& run_index,
                int total_runs, std::vector<RunResult>& runs,
                std::vector<RunResult>& registrations) {
  const Box bounds = rayBounds(set, o.max_range);
  checkGridSize(o, set, bounds);
  for (double resolution : o.resolutions) {
    const size_t first = runs.size();
    std::map<std::string, std::unique_ptr<NdtMap>> ndt_maps;  // kept for the comparisons
    for (const PlannedRun& p : plan) {
      std::unique_ptr<MappingSystem> system = makeSystem(p, resolution, o.max_range, bounds);
      char title[200];
      std::snprintf(title, sizeof title, "run %d/%d %s %.2f m %s", ++run_index, total_runs,
                    set.name.c_str(), resolution, system->label().c_str());
      progress.start(title, set.scans.size() * size_t(o.repeats));
      RunResult r = runSystem(*system, set, o.repeats, progress);
      r.kind = p.kind;
      r.threads = p.threads;
      r.resolution = resolution;
      if (auto* ndt = dynamic_cast<NdtomSystem*>(system.get()))
        ndt_maps[r.label] = ndt->releaseMap();
      runs.push_back(std::move(r));
    }
    compareNdtomMaps(runs, first, ndt_maps);
    runRegistrations(set, o, threads, ndt_maps, progress, run_index, total_runs, registrations);
    // Thread speed-ups once more, each multi-thread system side by side with one thread.
    for (size_t i = first; i < runs.size(); ++i) {
      RunResult& r = runs[i];
      if (!isNdtom(r.kind) || r.threads <= 1) continue;
      std::unique_ptr<MappingSystem> one = makeSystem({r.kind, 1}, resolution, o.max_range, bounds);
      std::unique_ptr<MappingSystem> many =
          makeSystem({r.kind, r.threads}, resolution, o.max_range, bounds);
      char title[200];
      std::snprintf(title, sizeof title, "run %d/%d %s %.2f m %s side by side with %s", ++run_index,
                    total_runs, set.name.c_str(), resolution, r.label.c_str(),
                    one->label().c_str());
      const double replay_seconds = r.totalSeconds() / std::max(r.repeats, 1);  // t > 1 alone
      const int repeats = pairedRepeats(replay_seconds, std::max(o.repeats, kMinPairedRepeats),
                                        kMinPairedSeconds);
      progress.start(title, 2 * set.scans.size() * size_t(repeats));
      const PairedSeconds paired = runPaired(*one, *many, set, repeats, progress);
      if (paired.second > 0) r.paired_speedup = paired.first / paired.second;
    }
  }
}

/// FILE.csv -> FILE.stages.csv (any other name: NAME.stages.csv).
std::string stagesCsvPath(const std::string& csv) {
  const std::string ext = ".csv";
  const bool has_ext =
      csv.size() > ext.size() && csv.compare(csv.size() - ext.size(), ext.size(), ext) == 0;
  return (has_ext ? csv.substr(0, csv.size() - ext.size()) : csv) + ".stages.csv";
}

void printScaling(const std::vector<RunResult>& runs, const std::vector<RunResult>& registrations) {
  if (!registrations.empty()) {
    std::cout << "\nRegistration (P2D, from the pose moved 0.3 m and 3 deg; the pyramid built "
                 "by a first call, timed on its own as pyramid/t<threads>):\n\n| dataset | system | res (m) | scans | median ms/scan | "
                 "CPU/wall | same poses as /t1 |\n|---|---|---:|---:|---:|---:|---|\n";
    for (const RunResult& r : registrations) {
      char line[300];
      std::snprintf(line, sizeof line, "| %s | %s | %.2f | %zu | %.2f | %.2f | %s |\n",
                    r.dataset.c_str(), r.label.c_str(), r.resolution, r.scan_seconds.size(),
                    r.medianSeconds() * 1e3, r.cpuPerWall(),
                    r.same_poses_as_t1 ? (*r.same_poses_as_t1 ? "yes" : "NO") : "-");
      std::cout << line;
    }
  }
  std::vector<RunResult> all = runs;
  all.insert(all.end(), registrations.begin(), registrations.end());
  std::cout << "\nWhere the time goes, per scan (serial: on the calling thread alone; parallel "
               "wall: regions on the worker threads; busy: their tasks' time summed over "
               "threads):\n\n"
            << stagesTable(all)
            << "\nBeyond the threads measured: Amdahl's S(n) = 1 / ((1 - p) + p / n), p the "
               "one-thread run's time in parallel regions (an upper bound: no spinning, "
               "imbalance or memory bandwidth):\n\n"
            << amdahlTable(all);
}

ScanSet loadDataset(const std::string& name, int max_scans) {
  if (name == kSyntheticDataset)
    return generateSyntheticScans(max_scans > 0 ? max_scans : kDefaultSyntheticScans);
  return loadScanDirectory(name, max_scans);
}

void printReport(const BenchOptions& o, const std::vector<ScanSet>& sets,
                 const std::vector<RunResult>& runs, const std::vector<RunResult>& registrations) {
  std::cout << "## ndtom-bench results\n\nCPU: " << apps::cpuDescription()
            << "\nBuild: " << apps::buildDescription() << "\nMax range: "
            << (std::isinf(o.max_range) ? std::string("none") : std::to_string(o.max_range) + " m")
            << ", repeats: " << o.repeats << ", insertion only (timed per scan)\n";
  for (const ScanSet& s : sets) {
    const Box box = rayBounds(s, o.max_range);
    const Eigen::Vector3d extent = box.max - box.min;
    std::printf(
        "Dataset %s: %zu scans, %zu points (%zu invalid dropped), rays within a box of "
        "%.1f x %.1f x %.1f m (the dense grid's extent)\n",
        s.name.c_str(), s.scans.size(), s.totalPoints(), s.dropped_points, extent.x(), extent.y(),
        extent.z());
  }

  std::cout << "\n" << resultsTable(runs) << "\n" << comparisonTable(runs);
  printScaling(runs, registrations);
  std::cout << "\nTargets:\n";
  for (const ScanSet& s : sets)
    for (const std::string& line : checkTargets(runs, s.name))
      std::cout << "  [" << s.name << "] " << line << "\n";
  if (o.real_time_ms.empty()) return;
  std::cout << "\nReal time (median time per scan within the scan period):\n";
  for (const ScanSet& s : sets)
    for (double period : o.real_time_ms)
      for (const std::string& line : realTimeThresholds(runs, s.name, period))
        std::cout << "  [" << s.name << "] " << line << "\n";
}

int run(const BenchOptions& o) {
  std::vector<int> threads = o.threads;
  if (threads.empty()) threads = kCoreHasThreads ? std::vector<int>{1, 2} : std::vector<int>{1};
  if (!kCoreHasThreads)
    for (int t : threads)
      if (t != 1) throw std::runtime_error("--threads: this core has no threaded insertion");

  std::vector<ScanSet> sets;
  for (const std::string& d : o.datasets) {
    sets.push_back(loadDataset(d, o.max_scans));
    for (size_t i = 0; i + 1 < sets.size(); ++i)
      if (sets[i].name == sets.back().name)
        throw std::runtime_error("--dataset " + d + ": a dataset named " + sets.back().name +
                                 " is already given");
  }
  const std::vector<PlannedRun> plan = planRuns(o, threads);
  const auto multi_thread = std::count_if(plan.begin(), plan.end(), [](const PlannedRun& p) {
    return isNdtom(p.kind) && p.threads > 1;
  });
  const bool registers =
      o.registration_scans > 0 &&
      std::any_of(plan.begin(), plan.end(), [](const PlannedRun& p) { return isNdtom(p.kind); });
  const int total_runs =
      int(sets.size() * o.resolutions.size() *
          (plan.size() + size_t(multi_thread) + (registers ? threads.size() : 0)));
  apps::Progress progress(!o.quiet);
  std::vector<RunResult> runs, registrations;
  int run_index = 0;
  for (const ScanSet& set : sets)
    runDataset(set, o, plan, threads, progress, run_index, total_runs, runs, registrations);

  printReport(o, sets, runs, registrations);
  if (!o.csv_path.empty()) {
    writeCsv(o.csv_path, runs);
    std::vector<RunResult> all = runs;
    all.insert(all.end(), registrations.begin(), registrations.end());
    writeStagesCsv(stagesCsvPath(o.csv_path), all);
  }
  if (!o.plot_prefix.empty())
    for (const ScanSet& s : sets)
      writeTimePlot(o.plot_prefix + "_" + s.name + ".png", runs, s.name, o.real_time_ms);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return apps::runProgram("ndtom-bench", [&] {
    const BenchOptions options = parseArguments(argc, argv);
    if (options.help) {
      std::cout << helpText(argv[0]);
      return 0;
    }
    return run(options);
  });
}
