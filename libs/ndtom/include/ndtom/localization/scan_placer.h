// Tracking's step: one scan placed near where it is predicted. The registration from the
// prediction; if its verdict fails, from the last pose (a platform whose yaw swings between
// slow scans); then a search of x, y and yaw around the prediction. A scan none of them
// places is lost. Shared by the online mapper (ndtom::OnlineMapper) and ndtom-localize.
//
// Two rules keep a lidar from sliding where the scene does not hold it. Its rings on flat
// ground fall where the last scans' rings fell, so registered on every ground point a moving
// sensor seems to stand still (ndtom-worldgen's city: scans placed 1-10 m back along the
// street, from their true pose): only one in `ground_thinning` ground points is registered,
// and a second pass on every point frees only height, roll and pitch. Along a direction the
// scan leaves unconstrained (a corridor), the pose keeps the prediction.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "ndtom/localization/global_localization.h"
#include "ndtom/map/ndt_map.h"
#include "ndtom/registration/registration.h"

namespace ndtom {

struct PlacementOptions {
  RegistrationOptions registration;
  /// The recovery search's grid and scoring (its levels are fitted to the registration's,
  /// fittedToLevels).
  GlobalSearchOptions search;
  /// When the registrations from the prediction and from the last pose fail: x, y within this
  /// radius (m) and yaw within ± this range (degrees) of the prediction (Default: 4 m, 60°).
  double recovery_radius = 4.0;
  double recovery_yaw_deg = 60;
  /// Directions of the translation whose standard deviation (from the registration's
  /// covariance) exceeds this keep the prediction's component (Default: 0.1 m; inf: never).
  double weak_direction_sigma = 0.1;
  /// Of the scan points on its ground plane, one in this many take part in registration
  /// (Default: 100; 1: all, and no levelling pass).
  int ground_thinning = 100;
  /// A scan the whole pyramid cannot place is tried again without its finest level. Against
  /// a map of one scan, a sparse lidar's rings (32 x 450) leave each 0.4 m cell a piece of
  /// one ring, and the next scan's rings fall between them: 19 % of it matched at its true
  /// pose on the 0.4 m level, 96 % on the 0.8 m one. Lost, the second scan left the map one
  /// scan, and every later scan was lost the same way; placed, the map fills in and the
  /// finest level places the next scans (ndtom-worldgen's city: 1-2 scans of 500 need the
  /// retry). (Default: true.)
  bool retry_without_finest = true;
};

/// Throws std::invalid_argument("<option> = <value>: <why>") on the first bad value.
void validate(const PlacementOptions& options);

enum class PlacementOutcome { Tracked, Recovered, Lost };

struct Placement {
  /// Tracked: the registration from the prediction holds; Recovered: from the last pose or
  /// the search.
  PlacementOutcome outcome = PlacementOutcome::Lost;
  /// "prediction", "last pose", "local search" or "" (lost).
  std::string found_by;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< the prediction when lost
  RegistrationResult registration;  ///< the one that decided (its failure when lost)
  int registrations = 0;            ///< runs of the registration, the search's included
  int weak_directions = 0;          ///< translation directions that kept the prediction
  /// Placed by the retry without the finest level (retry_without_finest).
  bool without_finest = false;
  /// When lost: where the registration from the prediction (whole pyramid) put the scan, if
  /// only the free-space check refused it (RegistrationResult::refused_for_free_space_only),
  /// with the prediction kept along weak directions. Not good enough to map or to report,
  /// but a better guess of where the sensor is than the prediction.
  std::optional<Eigen::Isometry3d> refused_pose;
};

class ScanPlacer {
 public:
  /// Throws std::invalid_argument on bad options.
  explicit ScanPlacer(const PlacementOptions& options);
  ~ScanPlacer();
  ScanPlacer(ScanPlacer&&) noexcept;
  ScanPlacer& operator=(ScanPlacer&&) noexcept;

  /// Where `points` (sensor frame) are in `map`, predicted at `prediction`, the previous scan
  /// at `last_pose` (both sensor -> map).
  Placement place(const NdtMap& map, const std::vector<Eigen::Vector3d>& points,
                  const Eigen::Isometry3d& prediction, const Eigen::Isometry3d& last_pose);

  /// The search of the whole map (global localization) with the same registration.
  GlobalLocalizer& localizer() { return search_; }
  /// The registration (pin a pyramid here: the levelling pass uses the same one).
  NdtRegistration& registration() { return search_.registration(); }
  const PlacementOptions& options() const { return options_; }

 private:
  void registerFromStarts(const NdtMap& map, const std::vector<Eigen::Vector3d>& points,
                          const Eigen::Isometry3d& prediction, const Eigen::Isometry3d& last_pose,
                          Placement& placement);
  void level(const NdtMap& map, const std::vector<Eigen::Vector3d>& points, Placement& placement);
  void placeWithoutFinest(const NdtMap& map, const std::vector<Eigen::Vector3d>& points,
                          const Eigen::Isometry3d& prediction, const Eigen::Isometry3d& last_pose,
                          Placement& placement);
  void useLevels(size_t count);

  PlacementOptions options_;
  GlobalLocalizer search_;  // holds the registration (and its pyramid) for every use
  NdtRegistration leveller_;
};

const char* toString(PlacementOutcome outcome);

}  // namespace ndtom
