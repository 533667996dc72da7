#include "ndtom/online/online_mapper.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "ndtom/localization/motion_prediction.h"
#include "online/ground_thinning.h"
#include "online/registration_target.h"
#include "online/weak_directions.h"
#include "support/elapsed.h"
#include "support/option_error.h"

namespace ndtom {

void validate(const OnlineMapperOptions& o) {
  validate(o.registration);
  validate(fittedToLevels(o.search, o.registration.level_factors));
  validate(o.map);
  if (!(o.target_radius > 0 && std::isfinite(o.target_radius)))
    failOption("target_radius", o.target_radius, "must be finite and > 0");
  if (!(o.target_refresh_distance >= 0 && std::isfinite(o.target_refresh_distance)))
    failOption("target_refresh_distance", o.target_refresh_distance, "must be finite and >= 0");
  if (!(o.target_refresh_angle_deg >= 0 && o.target_refresh_angle_deg <= 180))
    failOption("target_refresh_angle_deg", o.target_refresh_angle_deg, "must be in [0, 180]");
  if (!(o.target_max_scans >= 1))
    failOption("target_max_scans", o.target_max_scans, "must be >= 1");
  if (!(o.recovery_radius >= 0 && o.recovery_radius <= 1000))
    failOption("recovery_radius", o.recovery_radius, "must be in [0, 1000]");
  if (!(o.recovery_yaw_deg >= 0 && o.recovery_yaw_deg <= 180))
    failOption("recovery_yaw_deg", o.recovery_yaw_deg, "must be in [0, 180]");
  if (!(o.weak_direction_sigma > 0))
    failOption("weak_direction_sigma", o.weak_direction_sigma, "must be > 0 (inf: never)");
  if (!(o.ground_thinning >= 1 && o.ground_thinning <= 1000))
    failOption("ground_thinning", o.ground_thinning, "must be in [1, 1000]");
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

RegistrationOptions withThreads(RegistrationOptions o, int threads) {
  o.threads = threads;
  return o;
}

// Three parameters, set mostly by the ground: a sixth of the points does (city drive: 35 ms
// a scan with 6000; with 1000, roll and pitch within 0.1° over the kilometre all the same).
RegistrationOptions levelling(RegistrationOptions o, int threads) {
  o.threads = threads;
  o.planar = false;
  o.level_only = true;
  o.max_points = std::min<size_t>(o.max_points, 1000);
  return o;
}

}  // namespace

struct OnlineMapper::Tracking {
  Tracking(const OnlineMapperOptions& o, const Eigen::Isometry3d& first_pose)
      : motion(first_pose),
        search(fittedToLevels(o.search, o.registration.level_factors),
               withThreads(o.registration, o.threads)),
        leveller(levelling(o.registration, o.threads)) {}

  /// The first registration start that the verdict accepts, else a search around the
  /// prediction; the step's outcome, pose and registration say which, if any.
  void place(const NdtMap& map, const std::vector<Eigen::Vector3d>& points,
             const OnlineMapperOptions& o, OnlineStep& step) {
    // Registered against the target's pyramid, judged against the map as it is.
    search.registration().pinPyramid(target.pyramid(), map.revision());
    struct Start {
      const char* name;
      Eigen::Isometry3d pose;
    };
    for (const Start& s : {Start{"prediction", step.prediction}, Start{"last pose", motion.lastPose()}}) {
      if (s.name != std::string("prediction") && s.pose.isApprox(step.prediction)) continue;
      ++step.registrations;
      try {
        step.registration = search.registration().align(map, points, s.pose);
      } catch (const std::invalid_argument& e) {  // no usable point, or nothing to match yet
        step.registration = RegistrationResult{};
        step.registration.failure = e.what();
        return;
      }
      if (step.registration.converged) {
        accept(step, s.name == std::string("prediction") ? OnlineOutcome::Tracked
                                                         : OnlineOutcome::Recovered,
               s.name);
        return;
      }
    }
    const GlobalLocalizationResult found =
        search.searchAround(map, points, step.prediction, o.recovery_radius, o.recovery_yaw_deg);
    step.registrations += int(found.refined + found.fully_refined);
    if (found.found) {
      step.registration = found.best;
      accept(step, OnlineOutcome::Recovered, "search");
    } else {
      step.registration.failure += "; search around the prediction: " + found.failure;
    }
  }

  /// With the ground thinned, height, roll and pitch rest on few points: a second pass on the
  /// finest level frees only those, on every point (the ground's rings cannot pull x and y).
  /// Kept if its verdict holds.
  void level(const NdtMap& map, const std::vector<Eigen::Vector3d>& points, OnlineStep& step) {
    leveller.pinPyramid(target.pyramid(), map.revision());
    const size_t finest = target.pyramid()->size() - 1;
    ++step.registrations;
    try {
      const RegistrationResult r =
          leveller.align(map, points, step.pose, NdtRegistration::Levels{finest, finest + 1});
      if (r.converged) step.pose = r.pose;
    } catch (const std::invalid_argument&) {  // no usable point: the pose stays
    }
  }

  static void accept(OnlineStep& step, OnlineOutcome outcome, const char* found_by) {
    step.outcome = outcome;
    step.found_by = found_by;
    step.pose = step.registration.pose;
  }

  ConstantVelocity motion;  // the first pose until the first scan is committed
  GlobalLocalizer search;  // holds the registration (and its pyramid of the target)
  NdtRegistration leveller;
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

OnlineStep OnlineMapper::locate(const std::vector<Eigen::Vector3d>& points, double time,
                                const std::optional<Eigen::Isometry3d>& odometry) {
  Tracking& t = *tracking_;
  if (!std::isfinite(time)) throw std::invalid_argument("OnlineMapper: the scan's time is not finite");
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
  if (t.target.update(map_, step.prediction, options_)) step.target_seconds = secondsSince(cut);
  t.place(map_, online::thinGround(points, options_.ground_thinning), options_, step);
  if (step.outcome == OnlineOutcome::Lost) {
    step.pose = step.prediction;
  } else {
    step.weak_directions = online::keepPredictionAlongWeakDirections(
        step.pose, step.prediction, step.registration.covariance, options_.weak_direction_sigma);
    if (options_.ground_thinning > 1 && !options_.registration.planar) t.level(map_, points, step);
  }
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
