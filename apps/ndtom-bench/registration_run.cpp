#include "registration_run.h"

#include <chrono>
#include <cmath>

#include "ndtom/registration/registration.h"
#include "ndtom_apps/process_clock.h"
#include "ndtom_apps/statistics.h"

namespace ndtom::bench {

Eigen::Isometry3d offsetGuess(const Eigen::Isometry3d& pose) {
  Eigen::Isometry3d guess = pose;
  guess.translation() += Eigen::Vector3d(0.24, 0.18, 0.0);  // 0.3 m
  guess.linear() = Eigen::AngleAxisd(3 * M_PI / 180, Eigen::Vector3d::UnitZ()) * pose.linear();
  return guess;
}

RunResult runRegistration(const NdtMap& map, const ScanSet& set, size_t scans, int threads,
                          apps::Progress& progress, std::vector<Eigen::Isometry3d>& poses,
                          RunResult& pyramid) {
  using Clock = std::chrono::steady_clock;
  RunResult r;
  r.dataset = set.name;
  r.label = "registration-p2d/t" + std::to_string(threads);
  r.threads = threads;
  r.resolution = map.options().resolution;
  r.repeats = 1;
  scans = std::min(scans, set.scans.size());
  // Back to the sensor frame, untimed.
  std::vector<std::vector<Eigen::Vector3d>> sensor(scans);
  for (size_t i = 0; i < scans; ++i) {
    const Eigen::Isometry3d to_sensor = set.scans[i].pose.inverse();
    sensor[i].reserve(set.scans[i].points.size());
    for (const Eigen::Vector3d& p : set.scans[i].points) sensor[i].push_back(to_sensor * p);
  }
  pyramid = r;  // same dataset, threads and resolution; nothing timed yet
  pyramid.label = "pyramid/t" + std::to_string(threads);
  RegistrationOptions o;
  o.threads = threads;
  StageProfile first_call;
  o.profile = &first_call;
  NdtRegistration registration(o);
  if (scans > 0) registration.align(map, sensor[0], offsetGuess(set.scans[0].pose));
  if (const StageTimes* built = first_call.find("pyramid")) {
    pyramid.stages.stages.push_back(*built);
    pyramid.scan_seconds.push_back(built->wall_seconds);
  }
  o.profile = &r.stages;
  registration.setOptions(o);  // same levels: the pyramid stays
  poses.clear();
  double seconds_done = 0;
  size_t points_done = 0;
  for (size_t i = 0; i < scans; ++i) {
    const Eigen::Isometry3d guess = offsetGuess(set.scans[i].pose);
    const double cpu_start = apps::processCpuSeconds();
    const auto start = Clock::now();
    const RegistrationResult result = registration.align(map, sensor[i], guess);
    const double seconds = apps::secondsSince(start);
    r.scan_cpu_seconds.push_back(apps::processCpuSeconds() - cpu_start);
    r.scan_seconds.push_back(seconds);
    r.points += sensor[i].size();
    poses.push_back(result.pose);
    seconds_done += seconds;
    points_done += sensor[i].size();
    progress.update(i + 1, points_done, seconds_done);
  }
  if (!r.scan_seconds.empty())
    r.repeat_median_seconds.push_back(apps::quantile(r.scan_seconds, 0.5));
  progress.finish();
  return r;
}

}  // namespace ndtom::bench
