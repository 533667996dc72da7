#include "run_result.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace ndtom::bench {

double quantile(std::vector<double> samples, double q) {
  if (samples.empty()) return 0;
  std::sort(samples.begin(), samples.end());
  const double pos = q * double(samples.size() - 1);
  const size_t i = size_t(std::floor(pos));
  if (i + 1 >= samples.size()) return samples.back();
  return samples[i] + (pos - double(i)) * (samples[i + 1] - samples[i]);
}

double RunResult::medianSeconds() const {
  return quantile(scan_seconds, 0.5);
}
double RunResult::medianCpuSeconds() const {
  return quantile(scan_cpu_seconds, 0.5);
}
double RunResult::p95Seconds() const {
  return quantile(scan_seconds, 0.95);
}

double RunResult::totalSeconds() const {
  return std::accumulate(scan_seconds.begin(), scan_seconds.end(), 0.0);
}

double RunResult::cpuPerWall() const {
  const double wall = totalSeconds();
  return wall > 0 ? std::accumulate(scan_cpu_seconds.begin(), scan_cpu_seconds.end(), 0.0) / wall
                  : 0;
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
