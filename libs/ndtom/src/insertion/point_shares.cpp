#include "insertion/point_shares.h"

#include <algorithm>
#include <vector>

#include "ndtom/map/insertion_report.h"

namespace ndtom {

namespace {
// Classifying, a ray's set-up and sending its hit, in cell visits (callgrind: about 300
// instructions a point against 33 a visit).
constexpr double kVisitsPerPoint = 9;
}  // namespace

double pointWork(const ScanContext& scan, const Eigen::Vector3d& point) {
  const Eigen::Vector3d ray = point - scan.origin;
  if (!ray.allFinite()) return kVisitsPerPoint;  // rejected unwalked
  const double range = ray.norm();
  double cells = ray.lpNorm<1>() * scan.geometry.invResolution();
  if (range > scan.options.max_range) cells *= scan.options.max_range / range;
  return kVisitsPerPoint + std::min(cells, double(kMaxRayCells));
}

std::pair<size_t, size_t> pointShare(const ScanContext& scan, const Eigen::Vector3d* points,
                                     size_t n, size_t ranks, size_t rank) {
  if (ranks <= 1) return {0, n};
  const size_t samples = (n + kShareStride - 1) / kShareStride;
  // before[s]: the work of the points ahead of sample s's stretch, each stretch weighted by
  // its first point.
  thread_local std::vector<double> before;
  before.resize(samples + 1);
  before[0] = 0;
  for (size_t s = 0; s < samples; ++s) {
    const size_t first = s * kShareStride;
    before[s + 1] = before[s] + pointWork(scan, points[first]) *
                                    double(std::min(kShareStride, n - first));
  }
  const auto start = [&](size_t r) {
    if (r == 0) return size_t(0);
    if (r >= ranks) return n;
    const double target = before[samples] * double(r) / double(ranks);
    const size_t s = size_t(std::lower_bound(before.begin(), before.end(), target) - before.begin());
    return std::min(n, s * kShareStride);
  };
  return {start(rank), start(rank + 1)};
}

}  // namespace ndtom
