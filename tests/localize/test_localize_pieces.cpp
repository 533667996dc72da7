// ndtom-localize's pieces: the constant-velocity prediction against trajectories whose
// motion is known, and the --initial pose parser.
#include <gtest/gtest.h>

#include <cmath>

#include "localize_options.h"
#include "motion_prediction.h"
#include "ndtom_apps/option_values.h"

using namespace ndtom::localizer;
using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace {

Isometry3d motionOf(const Vector3d& t, double angle, const Vector3d& axis) {
  Isometry3d m = Isometry3d::Identity();
  m.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  m.translation() = t;
  return m;
}

}  // namespace

TEST(MotionPrediction, ConstantVelocityContinuesAConstantMotion) {
  // A robot repeating one motion every 0.5 s is predicted exactly; with a step of 1 s the
  // prediction is the motion applied twice (the same screw, twice as far).
  const Isometry3d step = motionOf(Vector3d(0.4, 0.1, 0.02), 0.1, Vector3d(0.1, 0.2, 1));
  Isometry3d pose = motionOf(Vector3d(5, -2, 1), 0.3, Vector3d::UnitZ());
  ConstantVelocity cv(pose);
  EXPECT_TRUE(cv.predict(0).isApprox(pose));
  double t = 10;
  for (int k = 0; k < 5; ++k) {
    cv.update(pose, t);
    pose = pose * step;
    t += 0.5;
    if (k >= 1) {
      EXPECT_TRUE(cv.predict(t).isApprox(pose, 1e-12)) << k;
    }
  }
  EXPECT_TRUE(cv.predict(t + 0.5).isApprox(pose * step, 1e-12));
  EXPECT_TRUE(cv.lastPose().isApprox(pose * step.inverse()));
}

TEST(MotionPrediction, ScaledMotionIsAFractionOfTheScrew) {
  const Isometry3d m = motionOf(Vector3d(0.3, -0.2, 0.1), 0.2, Vector3d(0, 0, 1));
  EXPECT_TRUE(scaledMotion(m, 1).isApprox(m));
  EXPECT_TRUE(scaledMotion(m, 0).isApprox(Isometry3d::Identity()));
  const Isometry3d half = scaledMotion(m, 0.5);
  EXPECT_NEAR(Eigen::AngleAxisd(half.linear()).angle(), 0.1, 1e-12);
  EXPECT_TRUE((half * half).isApprox(m, 1e-12));
  EXPECT_TRUE(scaledMotion(m, 3).isApprox(m * m * m, 1e-12));
  EXPECT_TRUE(scaledMotion(m, -1).isApprox(m.inverse(), 1e-12));
}

TEST(LocalizeOptions, InitialPoseInTumOrder) {
  const Isometry3d p = parsePose("--initial", "1 2 3 0 0 0.7071067811865476 0.7071067811865476");
  EXPECT_TRUE(p.translation().isApprox(Vector3d(1, 2, 3)));
  EXPECT_TRUE((p.linear() * Vector3d::UnitX()).isApprox(Vector3d::UnitY(), 1e-12));
  for (const char* bad : {"1 2 3", "1 2 3 0 0 0 0", "1 2 3 0 0 0 x", "1 2 3 0 0 0 1 5", "nan 0 0 0 0 0 1"})
    EXPECT_THROW(parsePose("--initial", bad), ndtom::apps::UsageError) << bad;
}
