// Global localization: the pose of a scan in a map without an initial guess.
//
// The scan's ground gives the gravity direction and the sensor's height (roll, pitch and z);
// the map's ground, seen from above, bounds where the sensor can be. Hypotheses on a grid of
// x, y and yaw over that ground are scored on a coarse level of the map's pyramid, the best
// few are registered on the coarse levels, the best distinct poses of those on every level,
// and the best converged one wins, unless a clearly different pose scores almost as well
// (ambiguous: not found).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ndtom/map/ndt_map.h"
#include "ndtom/registration/registration.h"

namespace ndtom {

struct GlobalSearchOptions {
  double position_step = 2.0;  ///< grid of x, y hypotheses (Default: 2 m)
  double yaw_step_deg = 30;    ///< yaw hypotheses (Default: 30°: 12 of them)
  /// Pyramid level (a factor of RegistrationOptions::level_factors) the hypotheses are
  /// scored on (Default: 16, 3.2 m cells on a 0.2 m map: its wide Gaussians still rank a
  /// hypothesis 1.4 m and 15° off the truth near the top; on the 1.6 m level 6 of 30 scans at
  /// the map's edge were not among the best 10).
  int scoring_level_factor = 16;
  size_t scoring_points = 400;  ///< scan points scoring each hypothesis (Default: 400)
  /// The best hypotheses are registered on the levels down to this factor (Default: 10 of
  /// them, down to 4: 0.8 m cells on a 0.2 m map) ...
  size_t refined = 10;
  int coarse_refinement_factor = 4;
  /// ... and the best distinct poses of those on every level (Default: 3).
  size_t fully_refined = 3;
  /// The scan's ground may be tilted this much from the sensor's +z (Default: 45°).
  double max_sensor_tilt_deg = 45;
  /// Map Gaussians flatter than this slope count as ground (Default: 15°).
  double max_ground_slope_deg = 15;
  /// Not found when a pose farther than 1 m or 10° from the best scores at least this
  /// fraction of its score (Default: 0.9).
  double ambiguity_ratio = 0.9;
};

/// Throws std::invalid_argument naming the bad option.
void validate(const GlobalSearchOptions& options);

/// A search scores at most this many poses (each 400 points on a coarse level, a few µs;
/// 3,180 for the campus map, 12 per 4 m² of floor): past it, it is not run and says which
/// options make it smaller. The poses are not stored, only the best few per thread.
inline constexpr size_t kMaxSearchPoses = 4'000'000;
/// The poses `searchAround` scores with these options.
size_t searchAroundPoses(const GlobalSearchOptions& options, double radius, double yaw_range_deg);
/// `search` with its scoring and coarse refinement levels moved to the nearest of the
/// registration's `level_factors` (they score and sort on pyramid levels), when those leave
/// the defaults out.
GlobalSearchOptions fittedToLevels(GlobalSearchOptions search,
                                   const std::vector<int>& level_factors);

/// The ground in the scan: the sensor's up direction and height above it.
struct GravityGuess {
  bool found = false;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  ///< unit, sensor frame
  double height = 0;                              ///< sensor above the ground plane (m)
  size_t inliers = 0;                             ///< scan points on the ground plane
};

struct GlobalLocalizationResult {
  bool found = false;
  std::string failure;      ///< why not, if not found
  RegistrationResult best;  ///< the refined winner (its verdict: converged)
  GravityGuess gravity;
  size_t ground_columns = 0;     ///< x, y cells of the map with ground (global search)
  size_t hypotheses = 0;         ///< scored
  size_t refined = 0;            ///< registered on the coarse levels from
  size_t distinct = 0;           ///< distinct poses among those that converged there
  size_t fully_refined = 0;      ///< registered on every level
  size_t refined_converged = 0;  ///< of those, converged
  double scoring_seconds = 0, refining_seconds = 0, seconds = 0;
};

class GlobalLocalizer {
 public:
  /// Throws std::invalid_argument on bad options (the scoring level must be one of the
  /// registration's levels).
  GlobalLocalizer(const GlobalSearchOptions& search, const RegistrationOptions& registration);
  ~GlobalLocalizer();
  GlobalLocalizer(GlobalLocalizer&&) noexcept;
  GlobalLocalizer& operator=(GlobalLocalizer&&) noexcept;

  /// The pose of `scan` (sensor frame) in `map`; not found (with the reason) where the scan
  /// or the map has no ground or nothing matches. Throws std::invalid_argument for a scan
  /// without usable points.
  GlobalLocalizationResult localize(const NdtMap& map, const std::vector<Eigen::Vector3d>& scan);

  /// The same search around a pose (tracking's recovery): x, y within `radius` (m) of it on
  /// the position grid, yaw within ±`yaw_range_deg` on the yaw grid, z, roll and pitch as
  /// given. Needs no ground.
  GlobalLocalizationResult searchAround(const NdtMap& map, const std::vector<Eigen::Vector3d>& scan,
                                        const Eigen::Isometry3d& centre, double radius,
                                        double yaw_range_deg);

  /// The registration it refines with (its pyramid cache is shared with the caller's use).
  NdtRegistration& registration() { return registration_; }

 private:
  struct GroundCache;
  /// Pose `i` of a grid of `grid_size`; false where the grid has none at `i`.
  using PoseAt = std::function<bool(size_t i, Eigen::Isometry3d& pose)>;
  /// Scores the grid's poses, registers the best, and fills `result` (all but gravity and
  /// ground).
  void searchAmong(const NdtMap& map, const std::vector<Eigen::Vector3d>& scan, size_t grid_size,
                   const PoseAt& pose_at, GlobalLocalizationResult& result);

  GlobalSearchOptions options_;
  NdtRegistration registration_;
  std::unique_ptr<GroundCache> ground_;
};

/// The ground plane of a scan by RANSAC (fixed seed): the plane below the sensor, tilted at
/// most `max_tilt_deg` from the sensor's +z, with the most points within 5 cm.
GravityGuess findGround(const std::vector<Eigen::Vector3d>& scan, double max_tilt_deg);

}  // namespace ndtom
