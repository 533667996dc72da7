#include "ndtom/localization/global_localization.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "localization/ground_columns.h"
#include "registration/ndt_objective.h"
#include "registration/scan_levels.h"
#include "registration/usable_points.h"
#include "support/elapsed.h"
#include "support/option_error.h"
#include "support/parallel.h"

namespace ndtom {
namespace {

/// The rotation turning `up` (unit, sensor frame) onto the map's +z by the smallest angle.
Eigen::Matrix3d levelling(const Eigen::Vector3d& up) {
  return Eigen::Quaterniond::FromTwoVectors(up, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

using PoseAt = std::function<bool(size_t i, Eigen::Isometry3d& pose)>;

struct Hypothesis {
  Eigen::Isometry3d pose;
  double score = 0;
  size_t index = 0;  ///< in generation order: ties in score go to the first
};

/// The scan's points registration would use; throws if none.
std::vector<Eigen::Vector3d> usableScan(const std::vector<Eigen::Vector3d>& scan,
                                        const RegistrationOptions& o, const NdtMap& map) {
  std::vector<Eigen::Vector3d> usable =
      registration::usablePoints(scan, o.min_range, o.max_range, map.geometry().resolution());
  if (usable.empty())
    throw std::invalid_argument("global localization: the scan has no usable point");
  return usable;
}

bool farApart(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  const double angle = Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
  return (a.translation() - b.translation()).norm() > 1.0 || angle > 10 * M_PI / 180;
}

// x, y on the position grid within `radius` of a centre, yaw within ±yaw range on the yaw
// grid; indexed over the enclosing square so no pose is stored.
class SearchAroundGrid {
 public:
  SearchAroundGrid(const GlobalSearchOptions& o, double radius, double yaw_range_deg)
      : step_(o.position_step),
        yaw_step_(o.yaw_step_deg * M_PI / 180),
        radius_(radius),
        cells_(int64_t(std::floor(radius / o.position_step))),
        yaws_(int64_t(std::floor(yaw_range_deg / o.yaw_step_deg))) {}

  size_t side() const { return size_t(2 * cells_ + 1); }
  size_t yawCount() const { return size_t(2 * yaws_ + 1); }
  size_t size() const { return side() * side() * yawCount(); }
  bool inside(int64_t i, int64_t j) const {
    return std::hypot(double(i), double(j)) * step_ <= radius_ + 1e-9;
  }
  /// The x, y grid points inside the circle (one row at a time: no loop over the square).
  size_t inCircle() const {
    size_t n = 0;
    const double reach = radius_ / step_;
    for (int64_t i = -cells_; i <= cells_; ++i) {
      int64_t j = std::min<int64_t>(
          cells_, int64_t(std::sqrt(std::max(0.0, reach * reach - double(i * i)))) + 1);
      while (j >= 0 && !inside(i, j)) --j;
      if (j >= 0) n += size_t(2 * j + 1);
    }
    return n;
  }
  bool poseAt(size_t index, const Eigen::Isometry3d& centre, Eigen::Isometry3d& pose) const {
    const int64_t k = int64_t(index % yawCount()) - yaws_;
    const size_t cell = index / yawCount();
    const int64_t i = int64_t(cell / side()) - cells_, j = int64_t(cell % side()) - cells_;
    if (!inside(i, j)) return false;
    pose = centre;
    pose.linear() =
        Eigen::AngleAxisd(double(k) * yaw_step_, Eigen::Vector3d::UnitZ()) * centre.linear();
    pose.translation() += Eigen::Vector3d(double(i) * step_, double(j) * step_, 0);
    return true;
  }

 private:
  double step_, yaw_step_, radius_;
  int64_t cells_, yaws_;
};

std::string tooManyPoses(size_t poses, const char* grid, const char* advice) {
  return "the search would score " + std::to_string(poses) + " poses (" + grid + "), more than " +
         std::to_string(kMaxSearchPoses) + ": " + advice;
}

bool better(const Hypothesis& a, const Hypothesis& b) {
  return a.score > b.score || (a.score == b.score && a.index < b.index);
}

// Every pose of the grid scored on the scoring level (in parallel over poses: each score is
// one thread's sum); the best `keep`, best first, ties to the first generated. Only those are
// kept: memory stays a few poses per thread however fine the grid.
std::vector<Hypothesis> scoreHypotheses(const NdtMap& map, const std::vector<Eigen::Vector3d>& scan,
                                        size_t grid_size, const PoseAt& pose_at, size_t keep,
                                        NdtRegistration& registration,
                                        const GlobalSearchOptions& options, WorkerPool& pool,
                                        size_t& scored) {
  using namespace registration;
  const RegistrationOptions& ro = registration.options();
  // The scan at the scoring level, as the registration reduces it.
  const auto pyramid = registration.pyramidFor(map);
  size_t level = 0;
  while (pyramid->factor(level) != options.scoring_level_factor) ++level;
  RegistrationOptions scoring = ro;
  scoring.method = RegistrationMethod::P2D;
  scoring.max_points = options.scoring_points;
  const std::vector<ScanLevel> scan_levels =
      buildScanLevels(usableScan(scan, ro, map), {pyramid->resolution(level)}, scoring,
                      map.options().regularization);
  const NdtObjective objective(pyramid->level(level), scan_levels[0], RegistrationMethod::P2D,
                               scoreConstants(pyramid->resolution(level), ro.outlier_ratio), pool,
                               1);
  const size_t threads = size_t(ro.threads);
  std::vector<std::vector<Hypothesis>> best(threads);  // per thread, a heap: worst on top
  std::vector<size_t> counts(threads, 0);
  pool.run(threads, [&](size_t t) {
    Eigen::Isometry3d pose;
    for (size_t i = t; i < grid_size; i += threads) {
      if (!pose_at(i, pose)) continue;
      ++counts[t];
      best[t].push_back({pose, objective.evaluate(pose, false).score, i});
      std::push_heap(best[t].begin(), best[t].end(), better);
      if (best[t].size() > keep) {
        std::pop_heap(best[t].begin(), best[t].end(), better);
        best[t].pop_back();
      }
    }
  });
  std::vector<Hypothesis> all;
  for (size_t t = 0; t < threads; ++t) {
    all.insert(all.end(), best[t].begin(), best[t].end());
    scored += counts[t];
  }
  std::sort(all.begin(), all.end(), better);
  if (all.size() > keep) all.resize(keep);
  return all;
}

// The best `options.refined` hypotheses registered on the coarse levels; each distinct pose
// they reach once, with its best score, best first.
std::vector<RegistrationResult> refineCoarsely(const NdtMap& map,
                                               const std::vector<Eigen::Vector3d>& scan,
                                               const std::vector<Hypothesis>& hypotheses,
                                               NdtRegistration& registration,
                                               const GlobalSearchOptions& options,
                                               size_t& refined) {
  const auto& factors = registration.options().level_factors;
  const size_t coarse_levels =
      size_t(std::find(factors.begin(), factors.end(), options.coarse_refinement_factor) -
             factors.begin()) +
      1;
  std::vector<RegistrationResult> coarse;
  for (size_t i = 0; i < hypotheses.size() && refined < options.refined; ++i) {
    ++refined;
    RegistrationResult r = registration.align(map, scan, hypotheses[i].pose, {0, coarse_levels});
    if (!r.converged) continue;
    const auto same = std::find_if(coarse.begin(), coarse.end(), [&](const RegistrationResult& c) {
      return !farApart(c.pose, r.pose);
    });
    if (same == coarse.end())
      coarse.push_back(std::move(r));
    else if (r.score > same->score)
      *same = std::move(r);
  }
  std::stable_sort(
      coarse.begin(), coarse.end(),
      [](const RegistrationResult& a, const RegistrationResult& b) { return a.score > b.score; });
  return coarse;
}

// The best, unless a pose far from it scores nearly as well: then why not.
std::string ambiguity(const std::vector<RegistrationResult>& converged,
                      const RegistrationResult& best, double ambiguity_ratio) {
  for (const RegistrationResult& other : converged)
    if (farApart(other.pose, best.pose) && other.score >= ambiguity_ratio * best.score) {
      std::ostringstream why;
      why << "ambiguous: two poses " << (other.pose.translation() - best.pose.translation()).norm()
          << " m apart score " << best.score << " and " << other.score;
      return why.str();
    }
  return "";
}

}  // namespace

GlobalSearchOptions fittedToLevels(GlobalSearchOptions search, const std::vector<int>& levels) {
  if (levels.empty()) return search;
  auto nearest = [&](int wanted) {
    return *std::min_element(levels.begin(), levels.end(), [&](int a, int b) {
      return std::abs(a - wanted) < std::abs(b - wanted);
    });
  };
  search.scoring_level_factor = nearest(search.scoring_level_factor);
  search.coarse_refinement_factor = nearest(search.coarse_refinement_factor);
  return search;
}

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
  if (!(o.max_ground_slope_deg > 0 && o.max_ground_slope_deg < 90))
    failOption("max_ground_slope_deg", o.max_ground_slope_deg, "must be in (0, 90)");
  if (!(o.ambiguity_ratio > 0 && o.ambiguity_ratio <= 1))
    failOption("ambiguity_ratio", o.ambiguity_ratio, "must be in (0, 1]");
}

struct GlobalLocalizer::GroundCache {
  uint64_t revision = 0;
  bool valid = false;
  std::vector<global::GroundColumn> columns;
  WorkerPool pool;
};

GlobalLocalizer::GlobalLocalizer(const GlobalSearchOptions& search,
                                 const RegistrationOptions& registration)
    : options_(search), registration_(registration), ground_(std::make_unique<GroundCache>()) {
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
  // Gravity and height from the scan's ground; where the sensor can be from the map's.
  result.gravity =
      findGround(usableScan(scan, registration_.options(), map), options_.max_sensor_tilt_deg);
  if (!result.gravity.found) {
    result.failure = "no ground found in the scan (needed for roll, pitch and height)";
    result.seconds = secondsSince(start);
    return result;
  }
  if (!ground_->valid || ground_->revision != map.revision()) {
    ground_->columns =
        global::groundColumns(map, options_.position_step, options_.max_ground_slope_deg);
    ground_->revision = map.revision();
    ground_->valid = true;
  }
  result.ground_columns = ground_->columns.size();
  if (ground_->columns.empty()) {
    result.failure = "the map has no ground (flat occupied Gaussians) to stand on";
    result.seconds = secondsSince(start);
    return result;
  }
  const Eigen::Matrix3d level_rotation = levelling(result.gravity.up);
  const size_t yaws = size_t(std::max(1L, std::lround(360.0 / options_.yaw_step_deg)));
  const auto& columns = ground_->columns;
  const PoseAt pose_at = [&](size_t i, Eigen::Isometry3d& pose) {
    const global::GroundColumn& column = columns[i / yaws];
    pose.setIdentity();
    pose.linear() =
        Eigen::AngleAxisd(2 * M_PI * double(i % yaws) / double(yaws), Eigen::Vector3d::UnitZ()) *
        level_rotation;
    pose.translation() =
        Eigen::Vector3d(column.centre.x(), column.centre.y(), column.z + result.gravity.height);
    return true;
  };
  const size_t poses = columns.size() * yaws;
  if (poses > kMaxSearchPoses) {
    result.failure =
        tooManyPoses(poses, "ground columns x yaws", "raise position_step or yaw_step_deg");
  } else {
    searchAmong(map, scan, poses, pose_at, result);
  }
  result.seconds = secondsSince(start);
  return result;
}

size_t searchAroundPoses(const GlobalSearchOptions& o, double radius, double yaw_range_deg) {
  const SearchAroundGrid grid(o, radius, yaw_range_deg);
  return grid.inCircle() * grid.yawCount();
}

GlobalLocalizationResult GlobalLocalizer::searchAround(const NdtMap& map,
                                                       const std::vector<Eigen::Vector3d>& scan,
                                                       const Eigen::Isometry3d& centre,
                                                       double radius, double yaw_range_deg) {
  const auto start = Clock::now();
  GlobalLocalizationResult result;
  const SearchAroundGrid grid(options_, radius, yaw_range_deg);
  const size_t poses = grid.inCircle() * grid.yawCount();
  if (poses > kMaxSearchPoses) {
    result.failure = tooManyPoses(poses, "the circle's grid x yaws",
                                  "raise position_step, or lower the radius or the yaw range");
  } else {
    const PoseAt pose_at = [&](size_t i, Eigen::Isometry3d& pose) {
      return grid.poseAt(i, centre, pose);
    };
    searchAmong(map, scan, grid.size(), pose_at, result);
  }
  result.seconds = secondsSince(start);
  return result;
}

void GlobalLocalizer::searchAmong(const NdtMap& map, const std::vector<Eigen::Vector3d>& scan,
                                  size_t grid_size, const PoseAt& pose_at,
                                  GlobalLocalizationResult& result) {
  // Every hypothesis scored on one coarse level.
  const auto scoring_start = Clock::now();
  const std::vector<Hypothesis> hypotheses =
      scoreHypotheses(map, scan, grid_size, pose_at, options_.refined, registration_, options_,
                      ground_->pool, result.hypotheses);
  result.scoring_seconds = secondsSince(scoring_start);

  // The best few on the coarse levels; of the distinct poses they reach, the best few on
  // every level.
  const auto refining_start = Clock::now();
  const std::vector<RegistrationResult> coarse =
      refineCoarsely(map, scan, hypotheses, registration_, options_, result.refined);
  result.distinct = coarse.size();
  std::vector<RegistrationResult> converged;
  for (size_t i = 0; i < coarse.size() && i < options_.fully_refined; ++i) {
    ++result.fully_refined;
    RegistrationResult r = registration_.align(map, scan, coarse[i].pose);
    if (r.converged) converged.push_back(std::move(r));
  }
  result.refining_seconds = secondsSince(refining_start);
  result.refined_converged = converged.size();

  // The best of those, if no other pose scores nearly as well.
  if (converged.empty()) {
    result.failure = "none of the " + std::to_string(result.refined) +
                     " best hypotheses converged: the scan does not match the map";
    return;
  }
  const auto best = std::max_element(
      converged.begin(), converged.end(),
      [](const RegistrationResult& a, const RegistrationResult& b) { return a.score < b.score; });
  result.best = *best;
  result.failure = ambiguity(converged, *best, options_.ambiguity_ratio);
  result.found = result.failure.empty();
}

}  // namespace ndtom
