#include "tracking.h"

#include <chrono>

#include "motion_prediction.h"

namespace ndtom::localizer {

size_t TrackingResult::converged() const {
  size_t n = 0;
  for (const ScanRecord& s : scans) n += s.result.converged;
  return n;
}

TrackingResult track(const ndtom::NdtMap& map, mapper::ScanSource& source,
                     const Eigen::Isometry3d& initial, const ndtom::RegistrationOptions& options,
                     apps::Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  TrackingResult out;
  ndtom::NdtRegistration registration(options);
  ConstantVelocity motion(initial);
  progress.start("localizing", source.size());
  size_t points_done = 0;
  while (auto scan = source.next()) {
    ScanRecord record;
    record.index = out.scans.size();
    record.name = scan->name;
    record.time = scan->time;
    const std::vector<Eigen::Vector3d> points = mapper::pointsInFrame(*scan);
    record.points = points.size();
    record.prediction = motion.predict(scan->time);
    for (const Eigen::Isometry3d& start : {record.prediction, motion.lastPose()}) {
      if (record.attempts > 0 && start.isApprox(record.prediction)) break;  // no new start
      ++record.attempts;
      try {
        record.result = registration.align(map, points, start);
      } catch (const std::invalid_argument& e) {  // a scan without usable points
        record.result = ndtom::RegistrationResult{};
        record.result.pose = record.prediction;
        record.result.failure = e.what();
        break;
      }
      if (record.result.converged) break;
    }
    record.pose = record.result.converged ? record.result.pose : record.prediction;
    motion.update(record.pose, scan->time);
    points_done += record.points;
    out.scans.push_back(std::move(record));
    progress.update(out.scans.size(), points_done);
  }
  progress.finish();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace ndtom::localizer
