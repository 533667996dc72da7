// Whether two keyframes see the same place: the newer one's first scan registered in the older
// one's submap (from the pose graph's guess, else a search around it, else, for large drift,
// a global search of the submap), then the older one's first scan in the newer one's submap
// from what that found. The loop is accepted only when both verdicts hold, the two relative
// poses agree within their covariances, and the covariances leave no direction weak (a
// street of look-alike blocks registers well in the wrong block only along the street).
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "ndtom/localization/global_localization.h"
#include "ndtom/registration/registration.h"
#include "ndtom/slam/keyframes.h"

namespace ndtom {

struct LoopCheckOptions {
  /// Registration against a submap: the stricter verdict of a finished map (matched 0.4),
  /// levels as the online mapper's for submaps coarsened to twice its cell (Default: 8 4 2 1,
  /// matched 0.4, judged 0.3).
  RegistrationOptions registration = [] {
    RegistrationOptions r;
    r.level_factors = {8, 4, 2, 1};
    r.min_matched_fraction = 0.4;
    r.min_judged_fraction = 0.3;
    return r;
  }();
  GlobalSearchOptions search;
  /// One in this many ground points registers; a second pass on every point frees only
  /// height, roll and pitch (Default: 100, as the online mapper). With every ground point a
  /// scan's rings lock onto the rings of old scans taken nearby, and both directions agree
  /// on a pose pulled toward the old sensor (city: loops 0.7 m short, 1 cm disagreement).
  int ground_thinning = 100;
  /// Yaw searched around the guess (±degrees; Default: 20).
  double search_yaw_deg = 20;
  /// The two directions must agree within this (Default: 0.3 m, 1.5°) ...
  double max_disagreement_m = 0.3;
  double max_disagreement_deg = 1.5;
  /// ... and within the chi-square bound of their covariances plus `covariance_floor_*`
  /// (σ; Default: 0.05 m, 0.1°: the NDT covariance treats points as independent).
  double covariance_floor_m = 0.05;
  double covariance_floor_deg = 0.1;
  double max_chi2 = 16.81;  ///< 6 degrees of freedom, 99 %
  /// Neither registration may leave a translation direction with σ above this (Default: 0.1 m).
  double max_sigma_m = 0.1;
};

/// Throws std::invalid_argument("<option> = <value>: <why>") on the first bad value.
void validate(const LoopCheckOptions& options);

struct LoopCheck {
  bool accepted = false;
  std::string rejection;  ///< why not, if not accepted
  /// How the forward registration started: "guess", "local search", "global search".
  std::string found_by;
  /// The newer anchor in the older one's frame (older⁻¹·newer), as the forward one found it.
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();
  /// Of the relative pose's error, [translation, rotation vector] in its own frame (right
  /// perturbation: MRPT's SE(3) edges), floored by `covariance_floor_*`.
  Matrix6d covariance = Matrix6d::Identity();
  double disagreement_m = 0, disagreement_deg = 0, chi2 = 0;
  RegistrationResult forward, backward;
  double seconds = 0;
};

class LoopChecker {
 public:
  /// Throws std::invalid_argument on bad options.
  explicit LoopChecker(const LoopCheckOptions& options);
  ~LoopChecker();
  LoopChecker(LoopChecker&&) noexcept;
  LoopChecker& operator=(LoopChecker&&) noexcept;

  /// Checks a loop between `older` and `newer`, whose relative pose the graph guesses as
  /// `guess` (older⁻¹·newer) give or take `radius` metres.
  LoopCheck check(const Keyframe& older, const Keyframe& newer, const Eigen::Isometry3d& guess,
                  double radius, double max_local_radius);

 private:
  /// Registration from `guess`, ground thinned, then levelled on every point.
  RegistrationResult align(const NdtMap& map, const std::vector<Eigen::Vector3d>& scan,
                           const Eigen::Isometry3d& guess);
  RegistrationResult level(const NdtMap& map, const std::vector<Eigen::Vector3d>& scan,
                           RegistrationResult result);
  RegistrationResult refined(const NdtMap& map, const std::vector<Eigen::Vector3d>& scan,
                             const GlobalLocalizationResult& found);
  RegistrationResult forward(const Keyframe& older, const Keyframe& newer,
                             const Eigen::Isometry3d& guess, double radius, double max_local_radius,
                             LoopCheck& out);
  void judge(const Keyframe& newer, LoopCheck& out) const;

  LoopCheckOptions options_;
  GlobalLocalizer search_;
  NdtRegistration leveller_;
};

/// A covariance of a pose's error in the map frame (δ = (v, ω): pose = (Exp(ω)·R, t + v)) as
/// the error of `relative` = anchor⁻¹·pose in its own frame: both blocks turned by Rᵀ.
Matrix6d covarianceInPoseFrame(const Matrix6d& map_covariance, const Eigen::Isometry3d& pose);

}  // namespace ndtom
