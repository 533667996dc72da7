#include "localize_accuracy.h"

#include <algorithm>
#include <cmath>

namespace ndtom::localizer {

std::optional<PoseError> errorOf(const ScanRecord& scan) {
  if (!scan.pose || !scan.reference || scan.outcome == Outcome::Lost) return std::nullopt;
  const Eigen::Isometry3d& p = *scan.pose;
  const Eigen::Isometry3d& r = *scan.reference;
  return PoseError{(p.translation() - r.translation()).norm(),
                   Eigen::AngleAxisd(r.linear().transpose() * p.linear()).angle() * 180 / M_PI};
}

std::optional<Accuracy> accuracyOf(const TrackingResult& tracking) {
  Accuracy a;
  double sum = 0, rotation_sum = 0;
  for (const ScanRecord& s : tracking.scans) {
    const auto e = errorOf(s);
    if (!e) continue;
    ++a.scans;
    sum += e->translation * e->translation;
    rotation_sum += e->rotation * e->rotation;
    a.max = std::max(a.max, e->translation);
    a.rotation_max = std::max(a.rotation_max, e->rotation);
  }
  if (a.scans == 0) return std::nullopt;
  a.rmse = std::sqrt(sum / double(a.scans));
  a.rotation_rmse = std::sqrt(rotation_sum / double(a.scans));
  return a;
}

}  // namespace ndtom::localizer
