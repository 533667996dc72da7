#include "run_result.h"

#include <numeric>

#include "ndtom_apps/statistics.h"

namespace ndtom::bench {

double RunResult::medianSeconds() const {
  return apps::quantile(scan_seconds, 0.5);
}
double RunResult::medianCpuSeconds() const {
  return apps::quantile(scan_cpu_seconds, 0.5);
}
double RunResult::p95Seconds() const {
  return apps::quantile(scan_seconds, 0.95);
}

double RunResult::totalSeconds() const {
  return std::accumulate(scan_seconds.begin(), scan_seconds.end(), 0.0);
}

double RunResult::totalCpuSeconds() const {
  return std::accumulate(scan_cpu_seconds.begin(), scan_cpu_seconds.end(), 0.0);
}

double RunResult::cpuPerWall() const {
  const double wall = totalSeconds();
  return wall > 0 ? totalCpuSeconds() / wall : 0;
}

double RunResult::pointsPerSecond() const {
  const double t = totalSeconds();
  return t > 0 ? double(points) * repeats / t : 0;
}

double RunResult::visitsPerSecond() const {
  const double t = totalSeconds();
  return t > 0 ? double(voxel_visits) * repeats / t : 0;
}

double RunResult::bytesPerCell() const {
  return map.cells > 0 ? double(map.memory_bytes) / double(map.cells) : 0;
}

const RunResult* findRun(const std::vector<RunResult>& runs, const std::string& dataset,
                         double resolution, const std::string& label) {
  for (const RunResult& r : runs)
    if (r.dataset == dataset && r.resolution == resolution && r.label == label) return &r;
  return nullptr;
}

}  // namespace ndtom::bench
