// Loop closure's core on the shipped BALM scans (a sensor at rest, 10 scans) and synthetic
// places: the candidates the graph's uncertainty allows, the edge covariance against sampled
// perturbations, and the two-way check removing a known drift or refusing a wrong place.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "ndtom/slam/keyframes.h"
#include "ndtom/slam/loop_candidates.h"
#include "ndtom/slam/loop_check.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

using namespace ndtom;
using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace {

const std::string kBalm = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld";

MapOptions mapOptions() {
  MapOptions m;
  m.resolution = 0.2;
  m.scan.max_range = 30;
  return m;
}

std::vector<Vector3d> scan(int i) {
  return io::readPcd(kBalm + "/full" + std::to_string(i) + ".pcd").points;
}

std::vector<Isometry3d> shippedPoses() {
  std::vector<Isometry3d> poses;
  for (const auto& p : io::readPoseFile(kBalm + "/poses.txt")) poses.push_back(p.pose);
  return poses;
}

// A keyframe of scans [first, last] placed at `frame`·pose_i (frame: the odometry's drift).
Keyframe keyframeOf(int first, int last, const Isometry3d& frame) {
  const std::vector<Isometry3d> poses = shippedPoses();
  Keyframe k(mapOptions());
  k.first_scan = size_t(first);
  k.anchor = frame * poses[size_t(first)];
  k.anchor_scan = scan(first);
  for (int i = first; i <= last; ++i) {
    const Isometry3d pose = frame * poses[size_t(i)];
    std::vector<Vector3d> world;
    for (const Vector3d& p : scan(i)) world.push_back(pose * p);
    k.submap.insertScan(world, pose.translation(), mapOptions().scan);
  }
  k.submap = k.submap.coarsened(2);  // as ndtom-slam keeps them: the checks' levels fit
  return k;
}

double angleDeg(const Isometry3d& a, const Isometry3d& b) {
  return Eigen::AngleAxisd((a.inverse() * b).linear()).angle() * 180 / M_PI;
}

}  // namespace

TEST(LoopCandidates, WithinTheRadiusAndFarEnoughBackAlongThePathNearestFirst) {
  LoopSearchOptions o;
  o.min_path_gap = 50;
  o.max_candidates = 2;
  // Keyframes 10 m apart along x, then back along y = 1: keyframe 9 is at x = 12.
  std::vector<KeyframePlace> k;
  for (int i = 0; i < 6; ++i) k.push_back({Vector3d(10.0 * i, 0, 0), 10.0 * i});
  for (int i = 0; i < 4; ++i) k.push_back({Vector3d(42.0 - 10 * i, 1, 0), 60.0 + 10 * i});
  EXPECT_EQ(loopCandidates(o, k, 9, 3.0), (std::vector<size_t>{1}));      // 10 m: 2.2 m off
  EXPECT_EQ(loopCandidates(o, k, 9, 12.0), (std::vector<size_t>{1, 2}));  // nearest first
  EXPECT_TRUE(loopCandidates(o, k, 9, 1.0).empty());
  EXPECT_TRUE(loopCandidates(o, k, 6, 30.0).empty());  // its neighbours on the path only
  EXPECT_DOUBLE_EQ(loopSearchRadius(o, 0), o.base_radius);
  EXPECT_DOUBLE_EQ(loopSearchRadius(o, 500), o.base_radius + 500 * o.drift_per_metre);
  EXPECT_DOUBLE_EQ(loopSearchRadius(o, 1e9), o.max_radius);
  EXPECT_THROW(loopCandidates(o, k, 10, 3.0), std::invalid_argument);
  o.drift_per_metre = -1;
  EXPECT_THROW(validate(o), std::invalid_argument);
}

// A new keyframe once the sensor moved or turned far enough from the anchor, measured in the
// anchor's frame: either alone suffices, and neither a shorter move nor a smaller turn does.
TEST(Keyframes, StartByDistanceOrTurnFromTheAnchor) {
  KeyframeOptions o;
  o.distance = 10;
  o.turn_deg = 30;
  const Isometry3d anchor =
      Eigen::Translation3d(5, -3, 1) * Eigen::AngleAxisd(2.0, Vector3d::UnitZ());
  const auto at = [&](const Vector3d& move, double yaw_deg) {
    return anchor * Eigen::Translation3d(move) *
           Eigen::AngleAxisd(yaw_deg * M_PI / 180, Vector3d(0.1, 0.2, 1).normalized());
  };
  EXPECT_FALSE(startsKeyframe(o, anchor, anchor));
  EXPECT_FALSE(startsKeyframe(o, anchor, at(Vector3d(6, 7.9, 0), 29)));  // 9.92 m, 29°
  EXPECT_TRUE(startsKeyframe(o, anchor, at(Vector3d(6, 8.1, 0), 0)));    // 10.08 m
  EXPECT_TRUE(startsKeyframe(o, anchor, at(Vector3d(0.5, 0, 0), 31)));
  EXPECT_TRUE(startsKeyframe(o, anchor, at(Vector3d(0.5, 0, 0), -31)));
  o.turn_deg = 0;
  EXPECT_THROW(validate(o), std::invalid_argument);
}

// The covariance of a registration's error (map frame) as the error of the relative pose in
// its own frame, against perturbations drawn from it and measured by the relative pose's log.
TEST(LoopCheck, EdgeCovarianceMatchesSampledPerturbations) {
  const Isometry3d anchor =
      Eigen::Translation3d(3, -2, 1) * Eigen::AngleAxisd(0.4, Vector3d(0.2, 0.1, 1).normalized());
  const Isometry3d pose = Eigen::Translation3d(12, 5, 0.5) *
                          Eigen::AngleAxisd(1.1, Vector3d(-0.1, 0.3, 1).normalized());
  Matrix6d a = Matrix6d::Random();
  const Matrix6d covariance = 1e-4 * (a * a.transpose() + Matrix6d::Identity());
  const Eigen::LLT<Matrix6d> llt(covariance);
  std::mt19937 rng(5);
  std::normal_distribution<double> n;
  Matrix6d sampled = Matrix6d::Zero();
  const int samples = 40000;
  const Isometry3d relative = anchor.inverse() * pose;
  for (int s = 0; s < samples; ++s) {
    Vector6d z;
    for (int i = 0; i < 6; ++i) z[i] = n(rng);
    const Vector6d d = llt.matrixL() * z;  // (v, ω): pose' = (Exp(ω)·R, t + v)
    Isometry3d moved = pose;
    moved.linear() =
        Eigen::AngleAxisd(d.tail<3>().norm(), d.tail<3>().normalized()).toRotationMatrix() *
        pose.linear();
    moved.translation() += d.head<3>();
    const Isometry3d e = relative.inverse() * (anchor.inverse() * moved);
    const Eigen::AngleAxisd aa(e.linear());
    Vector6d err;
    err << e.translation(), aa.angle() * aa.axis();
    sampled += err * err.transpose() / samples;
  }
  const Matrix6d predicted = covarianceInPoseFrame(covariance, pose);
  EXPECT_LT((sampled - predicted).norm(), 0.03 * predicted.norm()) << sampled << "\n\n"
                                                                   << predicted;
  EXPECT_GT((covariance - predicted).norm(), 0.1 * predicted.norm());  // the turn matters
}

// The newer keyframe's scans in a frame drifted by 1.2 m and 8°, as odometry would have them;
// the guess is what the drift makes of it. The check must find the true relative pose.
TEST(LoopCheck, RemovesAKnownDriftBothWays) {
  const std::vector<Isometry3d> poses = shippedPoses();
  const Isometry3d drift =
      Eigen::Translation3d(1.0, -0.7, 0.05) * Eigen::AngleAxisd(8 * M_PI / 180, Vector3d::UnitZ());
  const Keyframe older = keyframeOf(0, 4, Isometry3d::Identity());
  const Keyframe newer = keyframeOf(5, 9, drift);
  const Isometry3d guess = older.anchor.inverse() * newer.anchor;
  const Isometry3d truth = poses[0].inverse() * poses[5];
  ASSERT_GT((guess.translation() - truth.translation()).norm(), 1.0);  // the drift shows
  LoopChecker checker(LoopCheckOptions{});
  const LoopCheck c = checker.check(older, newer, guess, 3.0, 6.0);
  ASSERT_TRUE(c.accepted) << c.rejection;
  EXPECT_LT((c.relative.translation() - truth.translation()).norm(), 0.05);
  EXPECT_LT(angleDeg(c.relative, truth), 0.5);
  EXPECT_LT(c.disagreement_m, 0.05);
  EXPECT_TRUE(c.covariance.allFinite());
  EXPECT_GT(c.covariance.determinant(), 0);
}

// A newer keyframe whose first scan is the scene turned upside down, guessed at the older
// one's place: nothing matches it, and the check must say no.
TEST(LoopCheck, RefusesAPlaceItCannotSee) {
  const Keyframe older = keyframeOf(0, 4, Isometry3d::Identity());
  Keyframe newer = keyframeOf(5, 9, Isometry3d::Identity());
  for (Vector3d& p : newer.anchor_scan) p = Vector3d(p.x(), -p.y(), -p.z());
  LoopChecker checker(LoopCheckOptions{});
  const LoopCheck c = checker.check(older, newer, older.anchor.inverse() * newer.anchor, 2.0, 6.0);
  EXPECT_FALSE(c.accepted);
  EXPECT_FALSE(c.rejection.empty());
}
