// Online NDT-OM (the paper's online mapping, and its next step: NDT-OM with NDT registration
// as odometry): each scan is registered against the map built so far, coarse to fine, then
// inserted at the pose found. No pose from elsewhere is needed; a motion since the previous
// scan (wheel odometry) only improves the prediction.
//
// Per scan: predict (odometry, else constant velocity), register against the map's region
// around the prediction (occupied Gaussians only, so what moved away attracts nothing), and
// if the verdict fails retry from the last pose, then search x, y and yaw around the
// prediction (large turns between slow scans). Where the scene leaves a direction
// unconstrained (flat ground, a corridor: large variance in the registration's covariance)
// the pose keeps the prediction along it instead of sliding. A scan nothing places is lost
// and not inserted, so the map never takes a wrong pose. Its pose is the prediction, or, if
// only the free-space check refused the registration from the prediction, that
// registration's pose: the map may contradict itself where odometry comes back to streets it
// mapped long ago with drift, and the prediction alone would run off at the next turn. Where
// that pose also agrees with the prediction (free_space_overrule), the scan is placed and
// inserted: the motion and the map's Gaussians outvote the map's free space, which grazing
// rays or drift made wrong, and which the scan's own rays then correct.
//
// Threading: one scan at a time; `threads` run inside registration and insertion.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ndtom/localization/scan_placer.h"
#include "ndtom/map/ndt_map.h"
#include "ndtom/registration/registration.h"

namespace ndtom {

struct OnlineMapperOptions {
  MapOptions map;  ///< the map built (resolution, occupancy, insertion, memory budget)
  /// Registration, retries, recovery search and the rules against sliding, tuned for maps of
  /// a few scans. Its finest level is twice the map's cell (levels 16 8 4 2): a sparse
  /// lidar's single scan leaves 0.2 m cells with Gaussians shaped like its rings, which hold
  /// the next scan where the last one was (ndtom-worldgen's city: every scan lost from the
  /// second on at 0.2 m; 99 of 100 tracked at 0.4 m; the BALM sequence: 1.2 cm ATE either
  /// way). Its verdict asks a matched fraction of 0.25, not 0.4: a scan after a sharp turn
  /// matches less of a young map (BALM scan 22: 0.37 at its pose). The recovery search spans
  /// 2 m, not 4: the map is the scans' own, the prediction is near.
  PlacementOptions placement = [] {
    PlacementOptions p;
    p.registration.level_factors = {16, 8, 4, 2};
    p.registration.min_matched_fraction = 0.25;
    p.recovery_radius = 2.0;
    return p;
  }();
  /// The registration target: the pyramid of the map's blocks within this distance (m) of
  /// the predicted sensor position (Default: 50 m: a lidar's map reaches 30-40 m around it).
  /// It follows the map at every scan, redoing only the coarse cells over what the last scan
  /// changed.
  double target_radius = 50;
  /// The target's region is moved to the sensor once it is this far (m) from the region's
  /// centre (Default: 2 m; 0: every scan). Moving it looks at every block of the map to find
  /// those that join or leave.
  double target_refresh_distance = 2;
  /// A scan only the free-space check refused is placed and inserted all the same if its
  /// registration from the prediction ends within this distance (m), half the step the
  /// prediction made from the last pose, and 1° of the prediction (Default: 0.1 m; 0: never).
  /// A sparse lidar at a corner sees the side street's walls where rays that grazed them,
  /// edge-on, cleared the map (a 340 m block drive: 31 scans lost, 2.8 m ATE; with the
  /// overrule none, 0.06 m); a stalled pose, which the check is for, lies a step behind the
  /// prediction.
  double free_space_overrule = 0.1;
  /// Threads of registration and insertion (this, not placement.registration.threads); the
  /// result is the same for any count (Default: 1).
  int threads = 1;
};

/// Throws std::invalid_argument("<option> = <value>: <why>") on the first bad value.
void validate(const OnlineMapperOptions& options);

/// How a scan's pose was found.
enum class OnlineOutcome { First, Tracked, Recovered, Lost };
const char* toString(OnlineOutcome outcome);

struct OnlineStep {
  size_t index = 0;  ///< scans given to locate() before this one
  double time = 0;
  OnlineOutcome outcome = OnlineOutcome::Lost;
  /// What placed it: "first scan", "prediction", "last pose", "local search" or "" (lost).
  std::string found_by;
  Eigen::Isometry3d prediction = Eigen::Isometry3d::Identity();  ///< sensor -> map
  /// Kept: registered; when lost, the prediction or the refused registration's pose.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  RegistrationResult registration;  ///< the one that decided (empty for the first scan)
  int registrations = 0;            ///< runs of the registration, a search's refinements included
  int weak_directions = 0;          ///< translation directions that kept the prediction
  /// Placed only by the retry without the registration's finest level
  /// (PlacementOptions::retry_without_finest): `registration`'s last level is the one that
  /// placed it.
  bool without_finest = false;
  /// Lost, at the pose where the registration from the prediction put it, which only the
  /// free-space check refused (Placement::refused_pose): the next prediction follows it.
  bool pose_from_refused_registration = false;
  /// Tracked although only the free-space check refused it: its registration agreed with the
  /// prediction (OnlineMapperOptions::free_space_overrule).
  bool free_space_overruled = false;
  bool inserted = false;
  InsertionReport insertion;
  double target_seconds = 0;    ///< bringing the registration target up to the map
  double locate_seconds = 0;    ///< registration, retries and search
  double insert_seconds = 0;
};

class OnlineMapper {
 public:
  /// The first scan is placed at `first_pose` (sensor -> map). Throws std::invalid_argument on
  /// bad options.
  explicit OnlineMapper(const OnlineMapperOptions& options,
                        const Eigen::Isometry3d& first_pose = Eigen::Isometry3d::Identity());
  ~OnlineMapper();
  OnlineMapper(OnlineMapper&&) noexcept;
  OnlineMapper& operator=(OnlineMapper&&) noexcept;

  /// Where the scan (points in the sensor frame) taken at `time` (s; non-decreasing) was:
  /// `odometry`, if given, is the sensor's motion since the previous scan (previous⁻¹·this).
  /// Changes nothing but the step count: commit() finishes the scan. Throws
  /// std::invalid_argument for a non-finite time or one before the previous scan's.
  OnlineStep locate(const std::vector<Eigen::Vector3d>& points, double time,
                    const std::optional<Eigen::Isometry3d>& odometry = std::nullopt);
  /// Finishes a step of locate(): its `pose` (the caller may round it, e.g. to what a
  /// trajectory file holds) becomes the last pose, and unless the scan is lost its points,
  /// given in the map frame at that pose, are inserted. The map is unchanged if insertion
  /// throws (MemoryBudgetError, a bad origin).
  void commit(OnlineStep& step, const std::vector<Eigen::Vector3d>& points_map,
              const Eigen::Vector3d& sensor_origin_map);
  /// locate() and commit() at the registered pose; `sensor_origin` in the sensor frame.
  OnlineStep process(const std::vector<Eigen::Vector3d>& points,
                     const Eigen::Vector3d& sensor_origin, double time,
                     const std::optional<Eigen::Isometry3d>& odometry = std::nullopt);

  const NdtMap& map() const { return map_; }
  /// Replaces the map scans are registered against and inserted into (same resolution, else
  /// std::invalid_argument); the registration target is cut again from it. For a window of
  /// keyframe submaps, so that odometry never registers against its own drifted past.
  /// `frame_change` is where the new map's frame is (a pose p of the old frame is
  /// frame_change · p in the new one): the last pose moves with it, the motion since the scan
  /// before stays (a loop closure correcting the live map).
  void replaceMap(NdtMap map, const Eigen::Isometry3d& frame_change = Eigen::Isometry3d::Identity());
  /// The map, moved out: the mapper is empty after this.
  NdtMap takeMap();
  const OnlineMapperOptions& options() const { return options_; }

 private:
  struct Tracking;  // prediction, registration target, recovery search
  OnlineMapperOptions options_;
  NdtMap map_;
  std::unique_ptr<Tracking> tracking_;
};

}  // namespace ndtom
