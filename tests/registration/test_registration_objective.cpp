// The NDT objective's analytic gradient and Hessian (P2D and D2D) against central finite
// differences of its own score, in the parameters the optimiser steps in; and the Newton
// direction's uphill guarantee.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "core/synthetic_room.h"
#include "registration/ndt_objective.h"
#include "registration/newton_search.h"
#include "registration/pose_increment.h"

using namespace ndtom;
using namespace ndtom::registration;

namespace {

// Keeps the scan items whose world position at `pose` is at least `margin` from every cell
// face of `grid`: the steps of the finite differences then never move an item into another
// cell, where its 27 neighbours would change (a jump no derivative describes).
void keepAwayFromCellFaces(ScanLevel& level, const Eigen::Isometry3d& pose,
                           const GridGeometry& grid, double margin) {
  auto away = [&](const Eigen::Vector3d& item) {
    const Eigen::Vector3d scaled = (pose * item) * grid.invResolution();
    for (int a = 0; a < 3; ++a) {
      const double frac = scaled[a] - std::floor(scaled[a]);
      if (std::min(frac, 1 - frac) * grid.resolution() < margin) return false;
    }
    return true;
  };
  auto& points = level.points;
  points.erase(std::remove_if(points.begin(), points.end(), [&](const auto& p) { return !away(p); }),
               points.end());
  auto& gaussians = level.gaussians;
  gaussians.erase(std::remove_if(gaussians.begin(), gaussians.end(),
                                 [&](const ScanGaussian& g) { return !away(g.mean); }),
                  gaussians.end());
}

struct ObjectiveCase {
  NdtMap map = ndtom::testing::roomMap(0.4, 40000);
  GaussianLookup lookup{map, LookupOptions{true, false}};
  std::vector<ScanLevel> levels;
  WorkerPool pool;
  Eigen::Isometry3d pose;

  explicit ObjectiveCase(RegistrationMethod method) {
    // A scan of other samples in the sensor frame, at a pose 5 cm and 1° off the truth.
    const auto world = ndtom::testing::sampleRoom(3000, 11);
    std::vector<Eigen::Vector3d> sensor;
    for (const auto& p : world) sensor.push_back(p - ndtom::testing::kRoomSensor);
    RegistrationOptions o;
    o.method = method;
    o.max_points = 100000;
    o.voxel_ratio = 0.25;
    levels = buildScanLevels(sensor, {0.4}, o, map.options().regularization);
    pose.setIdentity();
    pose.translation() = ndtom::testing::kRoomSensor + Eigen::Vector3d(0.03, -0.04, 0.02);
    pose.linear() = Eigen::AngleAxisd(M_PI / 180, Eigen::Vector3d(1, 2, 3).normalized())
                        .toRotationMatrix();
    keepAwayFromCellFaces(levels[0], pose, map.geometry(), 1e-3);
  }
};

void expectDerivativesMatchFiniteDifferences(RegistrationMethod method) {
  ObjectiveCase s(method);
  ASSERT_GT(s.levels[0].size(), 100u);
  const NdtObjective objective(s.lookup, s.levels[0], method, scoreConstants(0.4, 0.55), s.pool,
                               1);
  const ObjectiveValue at = objective.evaluate(s.pose, true);
  ASSERT_GT(at.matched, s.levels[0].size() / 2);
  auto score = [&](const Vector6d& delta) {
    return objective.evaluate(applyIncrement(s.pose, delta), false).score;
  };
  // Central differences of the score; steps move no item more than 2e-5·(1 + 7 m) < 1 mm.
  const double hg = 1e-6, hh = 1e-5;
  Vector6d fd_gradient;
  Matrix6d fd_hessian;
  for (int k = 0; k < 6; ++k) {
    const Vector6d ek = Vector6d::Unit(k);
    fd_gradient[k] = (score(hg * ek) - score(-hg * ek)) / (2 * hg);
    for (int l = 0; l < 6; ++l) {
      const Vector6d el = Vector6d::Unit(l);
      fd_hessian(k, l) = (score(hh * (ek + el)) - score(hh * (ek - el)) -
                          score(hh * (el - ek)) + score(-hh * (ek + el))) /
                         (4 * hh * hh);
    }
  }
  const double g_scale = at.gradient.cwiseAbs().maxCoeff();
  const double h_scale = at.hessian.cwiseAbs().maxCoeff();
  ASSERT_GT(g_scale, 0);
  for (int k = 0; k < 6; ++k) {
    EXPECT_NEAR(at.gradient[k], fd_gradient[k], 1e-5 * g_scale) << "gradient " << k;
    for (int l = 0; l < 6; ++l)
      EXPECT_NEAR(at.hessian(k, l), fd_hessian(k, l), 1e-4 * h_scale) << "hessian " << k << l;
  }
}

}  // namespace

TEST(RegistrationObjective, P2dGradientAndHessianMatchFiniteDifferences) {
  expectDerivativesMatchFiniteDifferences(RegistrationMethod::P2D);
}

TEST(RegistrationObjective, D2dGradientAndHessianMatchFiniteDifferences) {
  expectDerivativesMatchFiniteDifferences(RegistrationMethod::D2D);
}

TEST(RegistrationObjective, SameValueForAnyThreadCount) {
  for (const auto method : {RegistrationMethod::P2D, RegistrationMethod::D2D}) {
    ObjectiveCase s(method);
    const auto constants = scoreConstants(0.4, 0.55);
    const ObjectiveValue one =
        NdtObjective(s.lookup, s.levels[0], method, constants, s.pool, 1).evaluate(s.pose, true);
    for (int threads : {2, 3, 7}) {
      const ObjectiveValue many = NdtObjective(s.lookup, s.levels[0], method, constants, s.pool,
                                               threads)
                                      .evaluate(s.pose, true);
      EXPECT_EQ(one.score, many.score);
      EXPECT_EQ(one.gradient, many.gradient);
      EXPECT_EQ(one.hessian, many.hessian);
      EXPECT_EQ(one.matched, many.matched);
    }
  }
}

TEST(RegistrationObjective, AscentDirectionGoesUphillForAnyHessian) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    Matrix6d a;
    for (int i = 0; i < 36; ++i) a(i) = n(rng);
    const Matrix6d hessian = a + a.transpose();  // indefinite in general
    Vector6d gradient;
    for (int i = 0; i < 6; ++i) gradient[i] = n(rng);
    const Vector6d d = ascentDirection(hessian, gradient);
    EXPECT_GT(gradient.dot(d), 0);
    // Where H is negative definite it is Newton's step.
    const Matrix6d negative = -(a * a.transpose() + Matrix6d::Identity());
    EXPECT_TRUE(ascentDirection(negative, gradient)
                    .isApprox(-negative.ldlt().solve(gradient), 1e-9));
  }
}
