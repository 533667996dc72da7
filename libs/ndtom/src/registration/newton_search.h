// Maximises an NdtObjective from a pose: Newton steps on the Hessian made negative definite
// (eigenvalues mirrored, Nocedal & Wright 3.4), capped in length, then a backtracking line
// search that accepts the first step length with the Armijo sufficient increase.
#pragma once

#include <Eigen/Geometry>
#include <array>

#include "registration/ndt_objective.h"

namespace ndtom::registration {

struct NewtonSettings {
  int max_iterations = 30;
  double translation_epsilon = 1e-4;  ///< m
  double rotation_epsilon = 1e-4;     ///< rad
  double max_translation_step = 1.0;  ///< m
  double max_rotation_step = 0.15;    ///< rad
  /// Parameters allowed to change (v, ω); the others keep their value.
  std::array<bool, 6> free = {true, true, true, true, true, true};
};

/// The parameters RegistrationOptions::planar leaves free: x, y and the rotation about z.
inline std::array<bool, 6> freeParameters(bool planar, bool level_only = false) {
  if (planar) return {true, true, false, false, false, true};
  if (level_only) return {false, false, true, true, true, false};
  return {true, true, true, true, true, true};
}

/// `m` with the rows and columns of fixed parameters zeroed and `diagonal` on their diagonal.
Matrix6d restrictTo(const Matrix6d& m, const std::array<bool, 6>& free, double diagonal);

struct NewtonOutcome {
  ObjectiveValue value;  ///< at the final pose
  int iterations = 0;
  int evaluations = 0;
  bool converged = false;
};

/// Moves `pose` uphill on `objective`.
NewtonOutcome newtonSearch(const NdtObjective& objective, Eigen::Isometry3d& pose,
                           const NewtonSettings& settings);

/// A Newton direction −H⁻¹g with H's eigenvalues made negative (|λ| mirrored, floored at a
/// small fraction of the largest), so that it always points uphill.
Vector6d ascentDirection(const Matrix6d& hessian, const Vector6d& gradient);

}  // namespace ndtom::registration
