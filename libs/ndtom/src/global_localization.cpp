#include "ndtom/global_localization.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "elapsed.h"
#include "global/floor_columns.h"
#include "option_error.h"
#include "parallel.h"
#include "registration/ndt_objective.h"
#include "registration/scan_levels.h"

namespace ndtom {
namespace {

/// The rotation turning `up` (unit, sensor frame) onto the map's +z by the smallest angle.
Eigen::Matrix3d levelling(const Eigen::Vector3d& up) {
  return Eigen::Quaterniond::FromTwoVectors(up, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

struct Hypothesis {
  Eigen::Isometry3d pose;
  double score = 0;
  size_t index = 0;  ///< in generation order: ties in score go to the first
};

/// The scan's finite points within the registration's range limits; throws if none.
std::vector<Eigen::Vector3d> usablePoints(const std::vector<Eigen::Vector3d>& scan,
                                          const RegistrationOptions& o) {
  std::vector<Eigen::Vector3d> usable;
  for (const Eigen::Vector3d& p : scan) {
    const double r = p.allFinite() ? p.norm() : -1;
    if (r >= o.min_range && r <= o.max_range && r < 1e6) usable.push_back(p);
  }
  if (usable.empty())
    throw std::invalid_argument("global localization: the scan has no usable point");
  return usable;
}

bool farApart(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  const double angle = Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
  return (a.translation() - b.translation()).norm() > 1.0 || angle > 10 * M_PI / 180;
}

}  // namespace

void validate(const GlobalSearchOptions& o) {
  if (!(o.position_step >= 0.1 && o.position_step <= 100))
    failOption("position_step", o.position_step, "must be in [0.1, 100] m");
  if (!(o.yaw_step_deg >= 1 && o.yaw_step_deg <= 180))
    failOption("yaw_step_deg", o.yaw_step_deg, "must be in [1, 180]");
  if (o.scoring_points < 10)
    failOption("scoring_points", double(o.scoring_points), "must be >= 10");
  if (o.refined < 1) failOption("refined", double(o.refined), "must be >= 1");
  if (o.fully_refined < 1) failOption("fully_refined", double(o.fully_refined), "must be >= 1");
  if (!(o.max_sensor_tilt_deg > 0 && o.max_sensor_tilt_deg <= 90))
    failOption("max_sensor_tilt_deg", o.max_sensor_tilt_deg, "must be in (0, 90]");
  if (!(o.max_floor_slope_deg > 0 && o.max_floor_slope_deg < 90))
    failOption("max_floor_slope_deg", o.max_floor_slope_deg, "must be in (0, 90)");
  if (!(o.ambiguity_ratio > 0 && o.ambiguity_ratio <= 1))
    failOption("ambiguity_ratio", o.ambiguity_ratio, "must be in (0, 1]");
}

struct GlobalLocalizer::FloorCache {
  uint64_t revision = 0;
  bool valid = false;
  std::vector<global::FloorColumn> columns;
  WorkerPool pool;
};

GlobalLocalizer::GlobalLocalizer(const GlobalSearchOptions& search,
                                 const RegistrationOptions& registration)
    : options_(search), registration_(registration), floor_(std::make_unique<FloorCache>()) {
  validate(options_);
  const auto& f = registration.level_factors;
  if (std::find(f.begin(), f.end(), options_.scoring_level_factor) == f.end())
    failOption("scoring_level_factor", options_.scoring_level_factor,
               "must be one of the registration's level_factors");
  if (std::find(f.begin(), f.end(), options_.coarse_refinement_factor) == f.end())
    failOption("coarse_refinement_factor", options_.coarse_refinement_factor,
               "must be one of the registration's level_factors");
}
GlobalLocalizer::~GlobalLocalizer() = default;
GlobalLocalizer::GlobalLocalizer(GlobalLocalizer&&) noexcept = default;
GlobalLocalizer& GlobalLocalizer::operator=(GlobalLocalizer&&) noexcept = default;

GlobalLocalizationResult GlobalLocalizer::localize(const NdtMap& map,
                                                   const std::vector<Eigen::Vector3d>& scan) {
  const auto start = Clock::now();
  GlobalLocalizationResult result;
  // Gravity and height from the scan's floor; where the sensor can be from the map's.
  result.gravity =
      findFloor(usablePoints(scan, registration_.options()), options_.max_sensor_tilt_deg);
  if (!result.gravity.found) {
    result.failure = "no floor found in the scan (needed for roll, pitch and height)";
    result.seconds = secondsSince(start);
    return result;
  }
  if (!floor_->valid || floor_->revision != map.revision()) {
    floor_->columns =
        global::floorColumns(map, options_.position_step, options_.max_floor_slope_deg);
    floor_->revision = map.revision();
    floor_->valid = true;
  }
  result.floor_columns = floor_->columns.size();
  if (floor_->columns.empty()) {
    result.failure = "the map has no floor (flat occupied Gaussians) to stand on";
    result.seconds = secondsSince(start);
    return result;
  }
  const Eigen::Matrix3d level_rotation = levelling(result.gravity.up);
  const int yaws = std::max(1, int(std::lround(360.0 / options_.yaw_step_deg)));
  std::vector<Eigen::Isometry3d> poses;
  poses.reserve(floor_->columns.size() * size_t(yaws));
  for (const global::FloorColumn& column : floor_->columns)
    for (int k = 0; k < yaws; ++k) {
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() =
          Eigen::AngleAxisd(2 * M_PI * k / yaws, Eigen::Vector3d::UnitZ()) * level_rotation;
      pose.translation() =
          Eigen::Vector3d(column.centre.x(), column.centre.y(), column.z + result.gravity.height);
      poses.push_back(pose);
    }
  searchAmong(map, scan, poses, result);
  result.seconds = secondsSince(start);
  return result;
}

GlobalLocalizationResult GlobalLocalizer::searchAround(const NdtMap& map,
                                                       const std::vector<Eigen::Vector3d>& scan,
                                                       const Eigen::Isometry3d& centre,
                                                       double radius, double yaw_range_deg) {
  const auto start = Clock::now();
  GlobalLocalizationResult result;
  const double step = options_.position_step;
  const int cells = int(std::floor(radius / step));
  const int yaws = int(std::floor(yaw_range_deg / options_.yaw_step_deg));
  std::vector<Eigen::Isometry3d> poses;
  for (int i = -cells; i <= cells; ++i)
    for (int j = -cells; j <= cells; ++j) {
      if (std::hypot(i, j) * step > radius + 1e-9) continue;
      for (int k = -yaws; k <= yaws; ++k) {
        Eigen::Isometry3d pose = centre;
        pose.linear() =
            Eigen::AngleAxisd(k * options_.yaw_step_deg * M_PI / 180, Eigen::Vector3d::UnitZ()) *
            centre.linear();
        pose.translation() += Eigen::Vector3d(i * step, j * step, 0);
        poses.push_back(pose);
      }
    }
  searchAmong(map, scan, poses, result);
  result.seconds = secondsSince(start);
  return result;
}

void GlobalLocalizer::searchAmong(const NdtMap& map, const std::vector<Eigen::Vector3d>& scan,
                                  const std::vector<Eigen::Isometry3d>& poses,
                                  GlobalLocalizationResult& result) {
  using namespace registration;
  const RegistrationOptions& ro = registration_.options();
  // The scan at the scoring level, as the registration reduces it.
  const auto pyramid = registration_.pyramidFor(map);
  size_t level = 0;
  while (pyramid->factor(level) != options_.scoring_level_factor) ++level;
  RegistrationOptions scoring = ro;
  scoring.method = RegistrationMethod::P2D;
  scoring.max_points = options_.scoring_points;
  const std::vector<Eigen::Vector3d> usable = usablePoints(scan, ro);
  const std::vector<ScanLevel> scan_levels =
      buildScanLevels(usable, {pyramid->resolution(level)}, scoring, map.options().regularization);
  const NdtObjective objective(pyramid->level(level), scan_levels[0], RegistrationMethod::P2D,
                               scoreConstants(pyramid->resolution(level), ro.outlier_ratio),
                               floor_->pool, 1);

  // Every hypothesis scored (in parallel over hypotheses: each score is one thread's sum).
  const auto scoring_start = Clock::now();
  std::vector<Hypothesis> hypotheses(poses.size());
  const size_t threads = size_t(ro.threads);
  floor_->pool.run(threads, [&](size_t t) {
    for (size_t i = t; i < poses.size(); i += threads)
      hypotheses[i] = {poses[i], objective.evaluate(poses[i], false).score, i};
  });
  result.hypotheses = hypotheses.size();
  std::sort(hypotheses.begin(), hypotheses.end(), [](const Hypothesis& a, const Hypothesis& b) {
    return a.score > b.score || (a.score == b.score && a.index < b.index);
  });
  result.scoring_seconds = secondsSince(scoring_start);

  // The best few on the coarse levels; of the distinct poses they reach, the best few on
  // every level.
  const auto refining_start = Clock::now();
  const auto& factors = ro.level_factors;
  const size_t coarse_levels =
      size_t(std::find(factors.begin(), factors.end(), options_.coarse_refinement_factor) -
             factors.begin()) +
      1;
  std::vector<RegistrationResult> coarse;
  for (size_t i = 0; i < hypotheses.size() && result.refined < options_.refined; ++i) {
    ++result.refined;
    RegistrationResult r = registration_.align(map, scan, hypotheses[i].pose, {0, coarse_levels});
    if (!r.converged) continue;
    const auto same = std::find_if(coarse.begin(), coarse.end(), [&](const RegistrationResult& c) {
      return !farApart(c.pose, r.pose);
    });
    if (same == coarse.end())
      coarse.push_back(std::move(r));
    else if (r.score > same->score)
      *same = std::move(r);
  }
  result.distinct = coarse.size();
  std::stable_sort(
      coarse.begin(), coarse.end(),
      [](const RegistrationResult& a, const RegistrationResult& b) { return a.score > b.score; });
  std::vector<RegistrationResult> converged;
  for (size_t i = 0; i < coarse.size() && i < options_.fully_refined; ++i) {
    ++result.fully_refined;
    RegistrationResult r = registration_.align(map, scan, coarse[i].pose);
    if (r.converged) converged.push_back(std::move(r));
  }
  result.refining_seconds = secondsSince(refining_start);
  result.refined_converged = converged.size();
  if (converged.empty()) {
    result.failure = "none of the " + std::to_string(result.refined) +
                     " best hypotheses converged: the scan does not match the map";
    return;
  }
  const auto best = std::max_element(
      converged.begin(), converged.end(),
      [](const RegistrationResult& a, const RegistrationResult& b) { return a.score < b.score; });
  result.best = *best;
  for (const RegistrationResult& other : converged)
    if (farApart(other.pose, best->pose) && other.score >= options_.ambiguity_ratio * best->score) {
      std::ostringstream why;
      why << "ambiguous: two poses " << (other.pose.translation() - best->pose.translation()).norm()
          << " m apart score " << best->score << " and " << other.score;
      result.failure = why.str();
      return;
    }
  result.found = true;
}

}  // namespace ndtom
