#include "registration/newton_search.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "registration/pose_increment.h"

namespace ndtom::registration {
namespace {

constexpr double kArmijo = 1e-4;  // sufficient increase: a tiny fraction of the linear model
constexpr int kMaxHalvings = 8;   // step lengths 1 .. 1/256

}  // namespace

Vector6d ascentDirection(const Matrix6d& hessian, const Vector6d& gradient) {
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(0.5 * (hessian + hessian.transpose()));
  const Vector6d lambda = eig.eigenvalues().cwiseAbs();
  const double floor_value = std::max(1e-9 * lambda.maxCoeff(), 1e-300);
  const Vector6d inverse = lambda.cwiseMax(floor_value).cwiseInverse();
  const Matrix6d& v = eig.eigenvectors();
  // For H' = −V·diag(|λ|)·Vᵀ: δ = −H'⁻¹g = V·diag(1/|λ|)·Vᵀg.
  return v * inverse.asDiagonal() * (v.transpose() * gradient);
}

Matrix6d restrictTo(const Matrix6d& m, const std::array<bool, 6>& free, double diagonal) {
  Matrix6d out = m;
  for (int k = 0; k < 6; ++k) {
    if (free[size_t(k)]) continue;
    out.row(k).setZero();
    out.col(k).setZero();
    out(k, k) = diagonal;
  }
  return out;
}

NewtonOutcome newtonSearch(const NdtObjective& objective, Eigen::Isometry3d& pose,
                           const NewtonSettings& settings) {
  NewtonOutcome out;
  out.value = objective.evaluate(pose, true);
  out.evaluations = 1;
  for (; out.iterations < settings.max_iterations;) {
    if (out.value.gradient.isZero(0.0)) {  // (checked on all parameters: cheap and rare)  // nothing to match, or an exact optimum
      out.converged = true;
      break;
    }
    // Fixed parameters: no gradient and a unit curvature, so their step is 0.
    Vector6d gradient = out.value.gradient;
    for (int k = 0; k < 6; ++k)
      if (!settings.free[size_t(k)]) gradient[k] = 0;
    Vector6d step = ascentDirection(restrictTo(out.value.hessian, settings.free, -1), gradient);
    const double t = step.head<3>().norm(), r = step.tail<3>().norm();
    const double cap = std::min({1.0, settings.max_translation_step / std::max(t, 1e-300),
                                 settings.max_rotation_step / std::max(r, 1e-300)});
    step *= cap;
    const double slope = gradient.dot(step);  // > 0: an ascent direction

    double alpha = 1;
    bool accepted = false;
    Eigen::Isometry3d trial_pose;
    ObjectiveValue trial;
    for (int k = 0; k <= kMaxHalvings; ++k, alpha *= 0.5) {
      trial_pose = applyIncrement(pose, alpha * step);
      trial = objective.evaluate(trial_pose, true);
      ++out.evaluations;
      if (trial.score >= out.value.score + kArmijo * alpha * slope) {
        accepted = true;
        break;
      }
    }
    if (!accepted) {  // no uphill step of a useful length: a (local) maximum
      out.converged = true;
      break;
    }
    pose = trial_pose;
    out.value = trial;
    ++out.iterations;
    if (alpha * t * cap < settings.translation_epsilon &&
        alpha * r * cap < settings.rotation_epsilon) {
      out.converged = true;
      break;
    }
  }
  return out;
}

}  // namespace ndtom::registration
