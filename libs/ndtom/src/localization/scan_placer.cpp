#include "ndtom/localization/scan_placer.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "localization/ground_thinning.h"
#include "localization/levelling.h"
#include "localization/refused_registration.h"
#include "localization/weak_directions.h"
#include "support/option_error.h"

namespace ndtom {
namespace {

bool levels(const PlacementOptions& o) {
  return o.ground_thinning > 1 && !o.registration.planar;
}

}  // namespace

void validate(const PlacementOptions& o) {
  validate(o.registration);
  validate(fittedToLevels(o.search, o.registration.level_factors));
  if (!(o.recovery_radius >= 0 && o.recovery_radius <= 1000))
    failOption("recovery_radius", o.recovery_radius, "must be in [0, 1000]");
  if (!(o.recovery_yaw_deg >= 0 && o.recovery_yaw_deg <= 180))
    failOption("recovery_yaw_deg", o.recovery_yaw_deg, "must be in [0, 180]");
  const size_t poses = searchAroundPoses(o.search, o.recovery_radius, o.recovery_yaw_deg);
  if (poses > kMaxSearchPoses)
    failOption("recovery_radius", o.recovery_radius,
               ("makes a search of " + std::to_string(poses) + " poses with position_step " +
                std::to_string(o.search.position_step) + " m and recovery_yaw_deg " +
                std::to_string(o.recovery_yaw_deg) + ", more than " +
                std::to_string(kMaxSearchPoses) + ": lower it or raise position_step")
                   .c_str());
  if (!(o.weak_direction_sigma > 0))
    failOption("weak_direction_sigma", o.weak_direction_sigma, "must be > 0 (inf: never)");
  if (!(o.ground_thinning >= 1 && o.ground_thinning <= 1000))
    failOption("ground_thinning", o.ground_thinning, "must be in [1, 1000]");
}

const char* toString(PlacementOutcome outcome) {
  switch (outcome) {
    case PlacementOutcome::Tracked:
      return "tracked";
    case PlacementOutcome::Recovered:
      return "recovered";
    case PlacementOutcome::Lost:
      return "lost";
  }
  return "?";
}

ScanPlacer::ScanPlacer(const PlacementOptions& options)
    : options_((validate(options), options)),
      search_(fittedToLevels(options.search, options.registration.level_factors),
              options.registration),
      leveller_(tracking::levellingOptions(options.registration)) {}

ScanPlacer::~ScanPlacer() = default;
ScanPlacer::ScanPlacer(ScanPlacer&&) noexcept = default;
ScanPlacer& ScanPlacer::operator=(ScanPlacer&&) noexcept = default;

Placement ScanPlacer::place(const NdtMap& map, const std::vector<Eigen::Vector3d>& points,
                            const Eigen::Isometry3d& prediction,
                            const Eigen::Isometry3d& last_pose) {
  struct AllLevelsAfter {  // the retry's levels end with the call, even if it throws
    ScanPlacer& placer;
    ~AllLevelsAfter() { placer.useLevels(SIZE_MAX); }
  } all_levels_after{*this};
  Placement placement;
  placement.pose = prediction;
  const std::vector<Eigen::Vector3d> thinned =
      tracking::thinGround(points, options_.ground_thinning);
  registerFromStarts(map, thinned, prediction, last_pose, placement);
  if (placement.outcome == PlacementOutcome::Lost)
    placeWithoutFinest(map, thinned, prediction, last_pose, placement);
  if (placement.outcome != PlacementOutcome::Lost) {
    placement.refused_pose.reset();
    placement.weak_directions = tracking::keepPredictionAlongWeakDirections(
        placement.pose, prediction, placement.registration.covariance,
        options_.weak_direction_sigma);
    if (levels(options_)) level(map, points, placement);  // on the levels that placed it
  } else if (placement.refused_pose) {  // its registration is the report's
    tracking::keepPredictionAlongWeakDirections(*placement.refused_pose, prediction,
                                                placement.registration.covariance,
                                                options_.weak_direction_sigma);
  }
  return placement;
}

// Every start runs the whole pyramid: starting the prediction's registration on the fine
// levels alone costs more, as the fine levels then iterate longer and more scans need the
// retries (doc/benchmarks.md, "Measurements behind the code").
void ScanPlacer::registerFromStarts(const NdtMap& map, const std::vector<Eigen::Vector3d>& points,
                                    const Eigen::Isometry3d& prediction,
                                    const Eigen::Isometry3d& last_pose, Placement& placement) {
  const auto accept = [&](PlacementOutcome outcome, const char* found_by) {
    placement.outcome = outcome;
    placement.found_by = found_by;
    placement.pose = placement.registration.pose;
  };
  // The registration from the prediction, if only the free-space check refused it.
  std::optional<RegistrationResult> refused;
  const bool new_start = !last_pose.isApprox(prediction);
  for (const bool from_prediction : {true, false}) {
    if (!from_prediction && !new_start) continue;
    ++placement.registrations;
    try {
      placement.registration =
          registration().align(map, points, from_prediction ? prediction : last_pose);
    } catch (const std::invalid_argument& e) {  // no usable point, or nothing to match yet
      placement.registration = RegistrationResult{};
      placement.registration.failure = e.what();
      return;
    }
    RegistrationResult& r = placement.registration;
    if (r.converged && (from_prediction || tracking::replacesRefused(r, refused, "the last pose's"))) {
      accept(from_prediction ? PlacementOutcome::Tracked : PlacementOutcome::Recovered,
             from_prediction ? "prediction" : "last pose");
      return;
    }
    if (from_prediction && r.refused_for_free_space_only) refused = r;
  }
  GlobalLocalizationResult found = search_.searchAround(
      map, points, prediction, options_.recovery_radius, options_.recovery_yaw_deg);
  placement.registrations += int(found.refined + found.fully_refined);
  if (found.found && tracking::replacesRefused(found.best, refused, "the search's")) {
    placement.registration = found.best;
    accept(PlacementOutcome::Recovered, "local search");
    return;
  }
  const std::string failure = placement.registration.failure + "; search around the prediction: " +
                              (found.found ? found.best.failure : found.failure);
  if (refused) {  // lost, where that registration put it: the report is its own
    placement.registration = std::move(*refused);
    placement.refused_pose = placement.registration.pose;
  }
  placement.registration.failure = failure;
}

void ScanPlacer::useLevels(size_t count) {
  registration().setLevelsInUse(count);
  leveller_.setLevelsInUse(count);
}

// A lost scan, tried again without the finest level; kept, with those levels still in use
// (the caller levels it on them), if that places it.
void ScanPlacer::placeWithoutFinest(const NdtMap& map, const std::vector<Eigen::Vector3d>& points,
                                    const Eigen::Isometry3d& prediction,
                                    const Eigen::Isometry3d& last_pose, Placement& placement) {
  const size_t levels = options_.registration.level_factors.size();
  if (!options_.retry_without_finest || levels < 3) return;  // two levels left at least
  Placement coarser;
  coarser.pose = prediction;
  coarser.registrations = placement.registrations;
  useLevels(levels - 1);
  registerFromStarts(map, points, prediction, last_pose, coarser);
  if (coarser.outcome == PlacementOutcome::Lost) {
    placement.registrations = coarser.registrations;
    placement.registration.failure +=
        "; without the finest level: " + coarser.registration.failure;
    return;
  }
  coarser.without_finest = true;
  placement = std::move(coarser);
}

// With the ground thinned: the levelling pass (levelling.h), kept if its verdict holds.
void ScanPlacer::level(const NdtMap& map, const std::vector<Eigen::Vector3d>& points,
                       Placement& placement) {
  const std::shared_ptr<const MapPyramid> pyramid = registration().pyramid();
  if (!pyramid) return;
  ++placement.registrations;
  try {
    if (const auto levelled =
            tracking::levelledPose(leveller_, pyramid, map, points, placement.pose))
      placement.pose = *levelled;
  } catch (const std::invalid_argument&) {  // no usable point: the pose stays
  }
}

}  // namespace ndtom
