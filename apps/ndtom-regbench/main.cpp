// ndtom-regbench: registers held-out lidar scans against a map of the others from initial
// errors of growing size, with NDT-OM's registration (P2D, D2D) and its peers (MRPT's ICP,
// PCL's NDT and GICP), all from the same starts in one process, and reports success, accuracy,
// time and NDT-OM's verdicts per system, threads and error level. See --help.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "level_summary.h"
#include "lidar_sequence.h"
#include "mrpt_icp_system.h"
#include "ndtom_apps/machine_info.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_apps/process_clock.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_system.h"
#include "pcl_peers.h"
#include "regbench_options.h"
#include "report.h"
#include "results_csv.h"
#include "success_plot.h"
#include "system_run.h"
#include "targets.h"

using namespace ndtom;
using namespace ndtom::regbench;

namespace {

/// The systems to run: those asked for, or every one this build has.
std::vector<SystemKind> chosenSystems(const RegbenchOptions& o) {
  if (o.systems.empty()) {
    std::vector<SystemKind> all = {SystemKind::NdtomP2D, SystemKind::NdtomD2D, SystemKind::MrptIcp};
    if (pclAvailable()) all.insert(all.end(), {SystemKind::PclNdt, SystemKind::PclGicp});
    return all;
  }
  for (SystemKind kind : o.systems)
    if ((kind == SystemKind::PclNdt || kind == SystemKind::PclGicp) && !pclAvailable())
      throw apps::UsageError(std::string("--systems: ") + systemName(kind) +
                             " needs PCL, which this build lacks (scripts/setup.sh --with-pcl, "
                             "then configure again)");
  return o.systems;
}

/// The output files' folders must exist: a long run should not end in "cannot write".
void checkOutputFolders(const RegbenchOptions& o) {
  for (const auto& [option, path] : {std::pair{"--csv", o.csv_path},
                                     {"--trials-csv", o.trials_csv_path},
                                     {"--plot", o.plot_path}}) {
    if (path.empty()) continue;
    const std::filesystem::path folder = std::filesystem::path(path).parent_path();
    if (!folder.empty() && !std::filesystem::is_directory(folder))
      throw std::runtime_error(std::string(option) + " " + path + ": no folder " + folder.string());
  }
}

struct PlannedRun {
  SystemKind kind;
  int threads;
};

std::vector<PlannedRun> planRuns(const std::vector<SystemKind>& systems,
                                 const std::vector<int>& threads) {
  std::vector<PlannedRun> plan;
  for (SystemKind kind : systems) {
    if (!usesThreads(kind)) {
      plan.push_back({kind, 1});
      continue;
    }
    for (int t : threads) plan.push_back({kind, t});
  }
  return plan;
}

/// The NDT-OM of the map scans, built once for every NDT-OM run (with its build time).
struct SharedNdtMap {
  std::unique_ptr<NdtMap> map;
  double seconds = 0;
};

/// Built if an NDT-OM system is to run, else empty.
SharedNdtMap sharedNdtMap(const std::vector<SystemKind>& systems, const LidarSequence& sequence,
                          const MapScans& map_scans, const RegbenchOptions& o) {
  SharedNdtMap ndt;
  if (std::none_of(systems.begin(), systems.end(), isNdtom)) return ndt;
  const auto t0 = std::chrono::steady_clock::now();
  ndt.map =
      std::make_unique<NdtMap>(buildNdtMap(sequence, map_scans.scans, o.resolution, o.max_range));
  ndt.seconds = apps::secondsSince(t0);
  return ndt;
}

std::unique_ptr<RegistrationSystem> makeSystem(const PlannedRun& p, const MapScans& map_scans,
                                               const SharedNdtMap& ndt) {
  switch (p.kind) {
    case SystemKind::NdtomP2D:
      return std::make_unique<NdtomSystem>(*ndt.map, RegistrationMethod::P2D, p.threads);
    case SystemKind::NdtomD2D:
      return std::make_unique<NdtomSystem>(*ndt.map, RegistrationMethod::D2D, p.threads);
    case SystemKind::MrptIcp:
      return std::make_unique<MrptIcpSystem>(map_scans);
    case SystemKind::PclNdt:
      return makePclNdt(map_scans);
    case SystemKind::PclGicp:
      return makePclGicp(map_scans);
  }
  throw std::logic_error("unknown system");
}

std::string joinedNumbers(const std::vector<int>& numbers) {
  std::string out;
  for (int n : numbers) out += (out.empty() ? "" : ", ") + std::to_string(n);
  return out;
}

void printSummary(const RegbenchOptions& o, const LidarSequence& sequence,
                  const MapScans& map_scans, const SharedNdtMap& ndt,
                  const std::vector<SystemRun>& runs, const std::vector<LevelSummary>& summaries,
                  const std::string& load_at_start) {
  std::cout << "## ndtom-regbench results\n\nCPU: " << apps::cpuDescription()
            << "\nLoad averages (1, 5, 15 min): " << load_at_start << " at the start, "
            << apps::loadAverages() << " at the end"
            << "\nBuild: " << apps::buildDescription() << "\nPeers: " << mrptVersion() << ", "
            << (pclAvailable() ? "PCL " + pclVersion()
                               : "no PCL in this build (pcl-ndt and "
                                 "pcl-gicp not run)")
            << "\n";
  std::printf(
      "Dataset %s: %zu scans, %zu points (%zu invalid dropped); held out: %s; map: the other "
      "%zu scans, %zu points within %g m of their sensor\n",
      sequence.name.c_str(), sequence.scans.size(), sequence.totalPoints(), sequence.dropped_points,
      joinedNumbers(o.held_out).c_str(), map_scans.scans.size(), map_scans.near_points.size(),
      o.max_range);
  if (ndt.map)
    std::printf("NDT-OM map: %g m cells, %zu Gaussians, built in %.2f s (rays cut at %g m)\n",
                o.resolution, ndt.map->numGaussians(), ndt.seconds, o.max_range);
  std::printf(
      "Starts: %d per held-out scan and error level, seed %u. Success: final pose within %g m "
      "and %g° of the reference. Times per registration: wall clock and process CPU time (on "
      "one thread, CPU below wall means other processes took the core), each system's first "
      "call left out (shown apart).\n\n",
      o.trials, o.seed, kSuccessMeters, kSuccessDegrees);
  std::cout << "### Systems\n\n"
            << systemsTable(runs) << "\n### Successes\n\n"
            << successMatrix(summaries, o.errors) << "\n### Per initial error\n\n"
            << levelsTable(summaries);
  const std::string pyramid = pyramidTable(summaries);
  if (!pyramid.empty())
    std::cout << "\n### NDT-OM: mean time and Newton steps per pyramid level\n\n" << pyramid;
  const std::string verdicts = verdictTable(runs, o.errors);
  if (!verdicts.empty()) std::cout << "\n### NDT-OM verdicts against the reference\n\n" << verdicts;
  const std::vector<std::string> targets = checkTargets(runs, summaries);
  if (!targets.empty()) {
    std::cout << "\nTargets (NDT-OM, one thread):\n";
    for (const std::string& line : targets) std::cout << "  " << line << "\n";
  }
}

int run(const RegbenchOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const std::string load_at_start = apps::loadAverages();
  const std::vector<SystemKind> systems = chosenSystems(o);
  checkOutputFolders(o);
  const LidarSequence sequence = loadLidarSequence(o.dataset);
  const MapScans map_scans = mapScans(sequence, o.held_out, o.max_range);
  const std::vector<Start> starts =
      planStarts(o.held_out, sequence.poses, o.errors, o.trials, o.seed);
  std::vector<const std::vector<Eigen::Vector3d>*> held_out_scans;
  for (int scan : o.held_out) held_out_scans.push_back(&sequence.scans[size_t(scan)]);

  const SharedNdtMap ndt = sharedNdtMap(systems, sequence, map_scans, o);
  const std::vector<PlannedRun> plan = planRuns(systems, o.threads);
  apps::Progress progress(!o.quiet);
  std::vector<SystemRun> runs;
  for (const PlannedRun& p : plan) {
    const auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<RegistrationSystem> system = makeSystem(p, map_scans, ndt);
    const double setup = isNdtom(p.kind) ? ndt.seconds : apps::secondsSince(t0);
    system->setScans(held_out_scans);
    char title[200];
    std::snprintf(title, sizeof title, "run %zu/%zu %s", runs.size() + 1, plan.size(),
                  system->label().c_str());
    progress.start(title, starts.size(), "registrations");
    SystemRun r = runSystem(*system, starts, o.held_out, sequence.poses, progress);
    r.kind = p.kind;
    r.threads = p.threads;
    r.setup_seconds = setup;
    runs.push_back(std::move(r));
  }

  std::vector<LevelSummary> summaries;
  for (const SystemRun& r : runs)
    for (LevelSummary& s : summarize(r, o.errors)) summaries.push_back(std::move(s));
  printSummary(o, sequence, map_scans, ndt, runs, summaries, load_at_start);
  if (!o.csv_path.empty()) writeLevelsCsv(o.csv_path, sequence.name, runs, summaries);
  if (!o.trials_csv_path.empty()) writeTrialsCsv(o.trials_csv_path, sequence.name, runs, o.errors);
  if (!o.plot_path.empty()) writeSuccessPlot(o.plot_path, sequence.name, summaries, o.errors);
  if (!o.quiet)
    std::fprintf(stderr, "ndtom-regbench: %zu registrations by %zu system runs in %.1f s\n",
                 starts.size() * runs.size(), runs.size(), apps::secondsSince(start));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return apps::runProgram("ndtom-regbench", [&] {
    const RegbenchOptions options = parseArguments(argc, argv);
    if (options.help) {
      std::cout << helpText(argv[0]);
      return 0;
    }
    return run(options);
  });
}
