#include "ndtom/online/online_mapper.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "ndtom/localization/motion_prediction.h"
#include "online/registration_target.h"
#include "support/elapsed.h"
#include "support/option_error.h"

namespace ndtom {

void validate(const OnlineMapperOptions& o) {
  validate(o.placement);
  validate(o.map);
  if (!(o.target_radius > 0 && std::isfinite(o.target_radius)))
    failOption("target_radius", o.target_radius, "must be finite and > 0");
  if (!(o.target_refresh_distance >= 0 && std::isfinite(o.target_refresh_distance)))
    failOption("target_refresh_distance", o.target_refresh_distance, "must be finite and >= 0");
  if (!(o.free_space_overrule >= 0 && std::isfinite(o.free_space_overrule)))
    failOption("free_space_overrule", o.free_space_overrule, "must be finite and >= 0 (0: never)");
  if (!(o.threads >= 1 && o.threads <= ScanOptions::kMaxThreads))
    failOption("threads", o.threads, "must be in [1, 256]");
}

const char* toString(OnlineOutcome outcome) {
  switch (outcome) {
    case OnlineOutcome::First:
      return "first";
    case OnlineOutcome::Tracked:
      return "tracked";
    case OnlineOutcome::Recovered:
      return "recovered";
    case OnlineOutcome::Lost:
      return "lost";
  }
  return "?";
}

namespace {

// Within `distance` (m; 0: never), half the step the prediction made from the last pose, and
// a degree of the prediction: a stalled pose, which the free-space check is for, lies a step
// behind it, however slow the sensor moves.
bool agreesWithPrediction(const Eigen::Isometry3d& pose, const Eigen::Isometry3d& prediction,
                          const Eigen::Isometry3d& last_pose, double distance) {
  const double step = (prediction.translation() - last_pose.translation()).norm();
  const double turned = Eigen::AngleAxisd(prediction.linear().transpose() * pose.linear()).angle();
  const double off = (pose.translation() - prediction.translation()).norm();
  return distance > 0 && off <= std::min(distance, 0.5 * step) && turned <= M_PI / 180;
}

PlacementOptions withThreads(PlacementOptions o, int threads) {
  o.registration.threads = threads;
  return o;
}

OnlineOutcome onlineOutcome(PlacementOutcome outcome) {
  switch (outcome) {
    case PlacementOutcome::Tracked:
      return OnlineOutcome::Tracked;
    case PlacementOutcome::Recovered:
      return OnlineOutcome::Recovered;
    case PlacementOutcome::Lost:
      break;
  }
  return OnlineOutcome::Lost;
}

}  // namespace

struct OnlineMapper::Tracking {
  Tracking(const OnlineMapperOptions& o, const Eigen::Isometry3d& first_pose)
      : motion(first_pose), placer(withThreads(o.placement, o.threads)) {}

  ConstantVelocity motion;  // the first pose until the first scan is committed
  ScanPlacer placer;
  online::RegistrationTarget target;
  size_t located = 0, committed = 0;
  std::optional<double> last_time;
  /// Whether the map has held a Gaussian: counting them walks the whole map, so they are
  /// counted only until there is one.
  bool registering = false;
};

OnlineMapper::OnlineMapper(const OnlineMapperOptions& options, const Eigen::Isometry3d& first_pose)
    : options_(options), map_(options.map) {
  validate(options_);
  if (!first_pose.matrix().allFinite())
    throw std::invalid_argument("OnlineMapper: the first pose is not finite");
  tracking_ = std::make_unique<Tracking>(options_, first_pose);
}

OnlineMapper::~OnlineMapper() = default;
OnlineMapper::OnlineMapper(OnlineMapper&&) noexcept = default;
OnlineMapper& OnlineMapper::operator=(OnlineMapper&&) noexcept = default;

NdtMap OnlineMapper::takeMap() {
  NdtMap out = std::move(map_);
  map_ = NdtMap(options_.map);
  return out;
}

void OnlineMapper::replaceMap(NdtMap map, const Eigen::Isometry3d& frame_change) {
  if (map.options().resolution != options_.map.resolution)
    throw std::invalid_argument("OnlineMapper::replaceMap: resolution " +
                                std::to_string(map.options().resolution) + " m, the mapper's is " +
                                std::to_string(options_.map.resolution) + " m");
  if (!frame_change.matrix().allFinite())
    throw std::invalid_argument("OnlineMapper::replaceMap: the frame change is not finite");
  map_ = std::move(map);
  tracking_->motion.moveFrame(frame_change);
  tracking_->target = online::RegistrationTarget{};
  tracking_->registering = map_.numGaussians() > 0;
}

OnlineStep OnlineMapper::locate(const std::vector<Eigen::Vector3d>& points, double time,
                                const std::optional<Eigen::Isometry3d>& odometry) {
  Tracking& t = *tracking_;
  if (!std::isfinite(time))
    throw std::invalid_argument("OnlineMapper: the scan's time is not finite");
  if (t.last_time && time < *t.last_time)
    throw std::invalid_argument("OnlineMapper: time goes backwards (" + std::to_string(time) +
                                " s after " + std::to_string(*t.last_time) + " s)");
  if (odometry && !odometry->matrix().allFinite())
    throw std::invalid_argument("OnlineMapper: the odometry is not finite");
  const auto start = Clock::now();
  OnlineStep step;
  step.index = t.located++;
  step.time = time;
  // Until the map holds a Gaussian there is nothing to register against: the scan is placed
  // where it is predicted (the first pose, for the first scan).
  if (!t.registering) t.registering = map_.numGaussians() > 0;
  if (!t.registering) {
    step.prediction = t.motion.predict(time);
    step.pose = step.prediction;
    step.outcome = OnlineOutcome::First;
    step.found_by = t.committed == 0 ? "first scan" : "map still empty";
    return step;
  }
  step.prediction = odometry ? t.motion.lastPose() * *odometry : t.motion.predict(time);
  const auto cut = Clock::now();
  t.target.update(map_, step.prediction, options_);
  step.target_seconds = secondsSince(cut);
  // Registered against the target's pyramid, judged against the map as it is.
  t.placer.registration().pinPyramid(t.target.pyramid(), map_.revision());
  Placement placed = t.placer.place(map_, points, step.prediction, t.motion.lastPose());
  step.outcome = onlineOutcome(placed.outcome);
  step.found_by = std::move(placed.found_by);
  step.pose = placed.pose;
  if (placed.outcome == PlacementOutcome::Lost && placed.refused_pose) {
    step.pose = *placed.refused_pose;
    if (agreesWithPrediction(step.pose, step.prediction, t.motion.lastPose(),
                             options_.free_space_overrule)) {
      step.outcome = OnlineOutcome::Tracked;
      step.found_by = "prediction, free space overruled";
      step.free_space_overruled = true;
    } else {
      step.pose_from_refused_registration = true;
    }
  }
  step.registration = std::move(placed.registration);
  step.registrations = placed.registrations;
  step.weak_directions = placed.weak_directions;
  step.without_finest = placed.without_finest;
  step.locate_seconds = secondsSince(start);
  return step;
}

void OnlineMapper::commit(OnlineStep& step, const std::vector<Eigen::Vector3d>& points_map,
                          const Eigen::Vector3d& sensor_origin_map) {
  Tracking& t = *tracking_;
  if (step.outcome != OnlineOutcome::Lost) {
    const auto start = Clock::now();
    ScanOptions scan = map_.options().scan;
    scan.threads = options_.threads;
    step.insertion = map_.insertScan(points_map, sensor_origin_map, scan);
    step.inserted = true;
    step.insert_seconds = secondsSince(start);
  }
  t.motion.update(step.pose, step.time);
  t.last_time = step.time;
  ++t.committed;
}

OnlineStep OnlineMapper::process(const std::vector<Eigen::Vector3d>& points,
                                 const Eigen::Vector3d& sensor_origin, double time,
                                 const std::optional<Eigen::Isometry3d>& odometry) {
  OnlineStep step = locate(points, time, odometry);
  std::vector<Eigen::Vector3d> points_map;
  points_map.reserve(points.size());
  for (const Eigen::Vector3d& p : points) points_map.push_back(step.pose * p);
  commit(step, points_map, step.pose * sensor_origin);
  return step;
}

}  // namespace ndtom
