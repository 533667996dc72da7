#include "ndtom/slam/loop_candidates.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "support/option_error.h"

namespace ndtom {

void validate(const LoopSearchOptions& o) {
  if (!(o.min_path_gap >= 0 && std::isfinite(o.min_path_gap)))
    failOption("loop min_path_gap", o.min_path_gap, "must be finite and >= 0");
  if (!(o.base_radius > 0 && std::isfinite(o.base_radius)))
    failOption("loop base_radius", o.base_radius, "must be finite and > 0");
  if (!(o.drift_per_metre >= 0 && o.drift_per_metre < 1))
    failOption("loop drift_per_metre", o.drift_per_metre, "must be in [0, 1)");
  if (!(o.max_radius >= o.base_radius && std::isfinite(o.max_radius)))
    failOption("loop max_radius", o.max_radius, "must be finite and >= base_radius");
  if (!(o.max_local_radius > 0 && std::isfinite(o.max_local_radius)))
    failOption("loop max_local_radius", o.max_local_radius, "must be finite and > 0");
  if (o.max_candidates < 1) failOption("loop max_candidates", 0, "must be >= 1");
}

double loopSearchRadius(const LoopSearchOptions& o, double path_since_closure) {
  return std::min(o.max_radius,
                  o.base_radius + o.drift_per_metre * std::max(0.0, path_since_closure));
}

std::vector<size_t> loopCandidates(const LoopSearchOptions& o,
                                   const std::vector<KeyframePlace>& keyframes, size_t current,
                                   double radius) {
  if (current >= keyframes.size()) throw std::invalid_argument("loopCandidates: no such keyframe");
  const KeyframePlace& now = keyframes[current];
  std::vector<std::pair<double, size_t>> near;
  for (size_t i = 0; i < current; ++i) {
    if (now.path_length - keyframes[i].path_length < o.min_path_gap) continue;
    const double d = (keyframes[i].position - now.position).head<2>().norm();
    if (d <= radius) near.emplace_back(d, i);
  }
  std::sort(near.begin(), near.end());
  std::vector<size_t> out;
  for (size_t i = 0; i < near.size() && out.size() < o.max_candidates; ++i)
    out.push_back(near[i].second);
  return out;
}

}  // namespace ndtom
