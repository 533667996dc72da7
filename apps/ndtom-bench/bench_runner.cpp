#include "bench_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "ndtom_apps/process_clock.h"
#include "ndtom_apps/process_memory.h"
#include "ndtom_apps/statistics.h"

namespace ndtom::bench {

RunResult runSystem(MappingSystem& system, const ScanSet& set, int repeats,
                    apps::Progress& progress) {
  using Clock = std::chrono::steady_clock;
  RunResult r;
  r.dataset = set.name;
  r.label = system.label();
  r.repeats = repeats;
  r.peak_rss_valid = true;
  const size_t scans = set.scans.size();
  double insert_seconds = 0;
  size_t points_done = 0;
  for (int rep = 0; rep < repeats; ++rep) {
    r.peak_rss_valid &= apps::resetPeakRss();
    const size_t rss_before = apps::currentRssBytes();
    system.reset();
    std::vector<double> times;
    for (size_t i = 0; i < scans; ++i) {
      const Scan& scan = set.scans[i];
      system.prepareScan(scan);
      const double cpu_start = apps::processCpuSeconds();
      const auto start = Clock::now();
      system.insertScan(scan);
      const double seconds = apps::secondsSince(start);
      r.scan_cpu_seconds.push_back(apps::processCpuSeconds() - cpu_start);
      times.push_back(seconds);
      if (rep == 0) {
        r.points += scan.points.size();
        r.voxel_visits += system.lastScanVisits(scan);
      }
      insert_seconds += seconds;
      points_done += scan.points.size();
      progress.update(rep * scans + i + 1, points_done, insert_seconds);
    }
    const size_t peak = apps::peakRssBytes();
    r.peak_rss_delta = std::max(r.peak_rss_delta, peak > rss_before ? peak - rss_before : 0);
    r.repeat_median_seconds.push_back(apps::quantile(times, 0.5));
    r.scan_seconds.insert(r.scan_seconds.end(), times.begin(), times.end());
  }
  r.map = system.mapSize();
  if (const StageProfile* stages = system.stageProfile()) r.stages = *stages;
  progress.finish();
  return r;
}

int pairedRepeats(double replay_seconds, int min_repeats, double min_seconds) {
  constexpr int kMaxRepeats = 100;  // a replay timed at ~0 s must not run forever
  if (!(replay_seconds > 0)) return std::max(min_repeats, 1);
  const double needed = std::ceil(min_seconds / replay_seconds);
  return std::max({min_repeats, 1, int(std::min(needed, double(kMaxRepeats)))});
}

PairedSeconds runPaired(MappingSystem& first, MappingSystem& second, const ScanSet& set,
                        int repeats, apps::Progress& progress) {
  using Clock = std::chrono::steady_clock;
  PairedSeconds total;
  const size_t scans = set.scans.size();
  size_t done = 0, points_done = 0;
  auto insert = [&](MappingSystem& system, size_t i) {
    const Scan& scan = set.scans[i];
    system.prepareScan(scan);
    const auto start = Clock::now();
    system.insertScan(scan);
    return apps::secondsSince(start);
  };
  for (int rep = 0; rep < repeats; ++rep) {
    first.reset();
    second.reset();
    for (size_t begin = 0; begin < scans; begin += kScansPerTurn) {
      const size_t end = std::min(scans, begin + kScansPerTurn);
      for (int side = 0; side < 2; ++side) {
        MappingSystem& system = side == 0 ? first : second;
        double& seconds = side == 0 ? total.first : total.second;
        for (size_t i = begin; i < end; ++i) {
          seconds += insert(system, i);
          points_done += set.scans[i].points.size();
          progress.update(++done, points_done, total.first + total.second);
        }
      }
    }
  }
  progress.finish();
  return total;
}

}  // namespace ndtom::bench
