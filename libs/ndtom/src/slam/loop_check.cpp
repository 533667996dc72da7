#include "ndtom/slam/loop_check.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "localization/ground_thinning.h"
#include "localization/levelling.h"
#include "support/elapsed.h"
#include "support/option_error.h"

namespace ndtom {

void validate(const LoopCheckOptions& o) {
  validate(o.registration);
  validate(o.search);
  if (!(o.ground_thinning >= 1 && o.ground_thinning <= 1000))
    failOption("loop ground_thinning", o.ground_thinning, "must be in [1, 1000]");
  if (!(o.search_yaw_deg >= 0 && o.search_yaw_deg <= 180))
    failOption("loop search_yaw_deg", o.search_yaw_deg, "must be in [0, 180]");
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"loop max_disagreement_m", o.max_disagreement_m},
        {"loop max_disagreement_deg", o.max_disagreement_deg},
        {"loop covariance_floor_m", o.covariance_floor_m},
        {"loop covariance_floor_deg", o.covariance_floor_deg},
        {"loop max_chi2", o.max_chi2},
        {"loop max_sigma_m", o.max_sigma_m}})
    if (!(value > 0 && std::isfinite(value))) failOption(name, value, "must be finite and > 0");
}

namespace {

Matrix6d turned(const Matrix6d& c, const Eigen::Matrix3d& r) {
  Matrix6d rot = Matrix6d::Zero();
  rot.topLeftCorner<3, 3>() = r;
  rot.bottomRightCorner<3, 3>() = r;
  return rot * c * rot.transpose();
}

/// [translation, rotation vector] of a small relative pose.
Vector6d errorOf(const Eigen::Isometry3d& d) {
  const Eigen::AngleAxisd aa(d.linear());
  Vector6d e;
  e << d.translation(), aa.angle() * aa.axis();
  return e;
}

double largestTranslationSigma(const Matrix6d& c) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(c.topLeftCorner<3, 3>());
  return std::sqrt(std::max(0.0, eig.eigenvalues().maxCoeff()));
}

}  // namespace

Matrix6d covarianceInPoseFrame(const Matrix6d& map_covariance, const Eigen::Isometry3d& pose) {
  return turned(map_covariance, pose.linear().transpose());
}

LoopChecker::LoopChecker(const LoopCheckOptions& options)
    : options_((validate(options), options)),
      search_(fittedToLevels(options.search, options.registration.level_factors),
              options.registration),
      leveller_(tracking::levellingOptions(options.registration)) {}

LoopChecker::~LoopChecker() = default;
LoopChecker::LoopChecker(LoopChecker&&) noexcept = default;
LoopChecker& LoopChecker::operator=(LoopChecker&&) noexcept = default;

RegistrationResult LoopChecker::level(const NdtMap& map, const std::vector<Eigen::Vector3d>& scan,
                                      RegistrationResult result) {
  const std::shared_ptr<const MapPyramid> pyramid = search_.registration().pyramid();
  if (!result.converged || !pyramid || options_.ground_thinning == 1) return result;
  if (const auto levelled = tracking::levelledPose(leveller_, pyramid, map, scan, result.pose))
    result.pose = *levelled;
  return result;
}

RegistrationResult LoopChecker::align(const NdtMap& map, const std::vector<Eigen::Vector3d>& scan,
                                      const Eigen::Isometry3d& guess) {
  const auto thinned = tracking::thinGround(scan, options_.ground_thinning);
  return level(map, scan, search_.registration().align(map, thinned, guess));
}

// A search's winner registered again as every check is; an ambiguous or failed search fails.
RegistrationResult LoopChecker::refined(const NdtMap& map, const std::vector<Eigen::Vector3d>& scan,
                                        const GlobalLocalizationResult& found) {
  if (found.found) return align(map, scan, found.best.pose);
  RegistrationResult failed = found.best;
  failed.converged = false;
  failed.failure = found.failure.empty() ? "the search found nothing" : found.failure;
  return failed;
}

RegistrationResult LoopChecker::forward(const Keyframe& older, const Keyframe& newer,
                                        const Eigen::Isometry3d& guess, double radius,
                                        double max_local_radius, LoopCheck& out) {
  const Eigen::Isometry3d start = older.anchor * guess;  // newer's anchor in older's frame
  const std::vector<Eigen::Vector3d>& scan = newer.anchor_scan;
  if (radius > max_local_radius) {
    out.found_by = "global search";  // needs the scan's ground: every point
    return refined(older.submap, scan, search_.localize(older.submap, scan));
  }
  out.found_by = "guess";
  RegistrationResult r = align(older.submap, scan, start);
  if (r.converged) return r;
  out.found_by = "local search";
  const auto thinned = tracking::thinGround(scan, options_.ground_thinning);
  return refined(
      older.submap, scan,
      search_.searchAround(older.submap, thinned, start, radius, options_.search_yaw_deg));
}

LoopCheck LoopChecker::check(const Keyframe& older, const Keyframe& newer,
                             const Eigen::Isometry3d& guess, double radius,
                             double max_local_radius) {
  const auto start = Clock::now();
  LoopCheck out;
  if (older.submap.numGaussians() == 0 || newer.submap.numGaussians() == 0) {
    out.rejection = "a submap without Gaussians";
    return out;
  }
  try {
    out.forward = forward(older, newer, guess, radius, max_local_radius, out);
    if (out.forward.converged) {
      out.relative = older.anchor.inverse() * out.forward.pose;
      // The older anchor where the forward result puts it in the newer one's frame.
      out.backward = align(newer.submap, older.anchor_scan, newer.anchor * out.relative.inverse());
    }
  } catch (const std::invalid_argument& e) {  // a scan without usable points
    out.rejection = e.what();
    out.seconds = secondsSince(start);
    return out;
  }
  judge(newer, out);
  out.seconds = secondsSince(start);
  return out;
}

void LoopChecker::judge(const Keyframe& newer, LoopCheck& out) const {
  const LoopCheckOptions& o = options_;
  if (!out.forward.converged) {
    out.rejection = "forward: " + (out.forward.failure.empty() ? "not found" : out.forward.failure);
    return;
  }
  if (!out.backward.converged) {
    out.rejection = "backward: " + out.backward.failure;
    return;
  }
  const Eigen::Isometry3d backward_relative =
      (newer.anchor.inverse() * out.backward.pose).inverse();
  const Eigen::Isometry3d d = out.relative.inverse() * backward_relative;
  const Vector6d e = errorOf(d);
  out.disagreement_m = e.head<3>().norm();
  out.disagreement_deg = e.tail<3>().norm() * 180 / M_PI;
  const Matrix6d forward_cov = covarianceInPoseFrame(out.forward.covariance, out.forward.pose);
  const Matrix6d backward_cov =
      turned(covarianceInPoseFrame(out.backward.covariance, out.backward.pose),
             backward_relative.linear().transpose());
  Matrix6d floor = Matrix6d::Zero();
  floor.diagonal().head<3>().setConstant(o.covariance_floor_m * o.covariance_floor_m);
  const double floor_rad = o.covariance_floor_deg * M_PI / 180;
  floor.diagonal().tail<3>().setConstant(floor_rad * floor_rad);
  out.covariance = forward_cov + floor;
  out.chi2 = e.dot((forward_cov + backward_cov + 2 * floor).ldlt().solve(e));
  const double sigma = std::max(largestTranslationSigma(out.forward.covariance),
                                largestTranslationSigma(out.backward.covariance));
  if (!out.covariance.allFinite() || !std::isfinite(out.chi2))
    out.rejection = "covariance not finite";
  else if (sigma > o.max_sigma_m)
    out.rejection = "a weak direction (sigma " + std::to_string(sigma) + " m)";
  else if (out.disagreement_m > o.max_disagreement_m ||
           out.disagreement_deg > o.max_disagreement_deg)
    out.rejection = "forward and backward disagree by " + std::to_string(out.disagreement_m) +
                    " m, " + std::to_string(out.disagreement_deg) + " deg";
  else if (out.chi2 > o.max_chi2)
    out.rejection = "forward and backward disagree beyond their covariance (chi2 " +
                    std::to_string(out.chi2) + ")";
  else
    out.accepted = true;
}

}  // namespace ndtom
