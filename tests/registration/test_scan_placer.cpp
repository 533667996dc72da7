// ScanPlacer, tracking's step: its two rules against sliding (ground thinning, weak
// directions) on constructed cases, and the placer on a simulated city drive, where a lidar's
// rings on flat ground hold a scan registered on all its points where the last one was.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <random>

#include "localization/ground_thinning.h"
#include "localization/refused_registration.h"
#include "localization/weak_directions.h"
#include "ndtom/localization/scan_placer.h"
#include "ndtom/online/online_mapper.h"

#ifdef NDTOM_HAVE_WORLD
#include "city_route.h"
#include "simulated_lidar.h"
#endif

using namespace ndtom;
using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

// A flat floor 1.8 m below the sensor and a wall: one in K floor points is kept, every wall
// point, in order.
TEST(ScanPlacerRules, GroundThinningKeepsOneInKGroundPoints) {
  std::vector<Vector3d> scan;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-10, 10), n(-0.01, 0.01);
  for (int i = 0; i < 5000; ++i) scan.emplace_back(u(rng), u(rng), -1.8 + n(rng));
  for (int i = 0; i < 1000; ++i)
    scan.emplace_back(6 + n(rng), u(rng), -1.5 + 0.2 * std::abs(u(rng)));
  const std::vector<Vector3d> thinned = tracking::thinGround(scan, 10);
  size_t floor = 0, wall = 0;
  for (const Vector3d& p : thinned) (p.z() < -1.7 ? floor : wall)++;
  EXPECT_EQ(floor, 500u);
  EXPECT_EQ(wall, 1000u);
  EXPECT_EQ(tracking::thinGround(scan, 1).size(), scan.size());
  // No ground (a scan of walls only): everything stays.
  const std::vector<Vector3d> walls(scan.begin() + 5000, scan.end());
  EXPECT_EQ(tracking::thinGround(walls, 10).size(), walls.size());
}

// A covariance loose along one direction (a corridor's axis): the pose keeps the prediction's
// component there and the registration's across it.
TEST(ScanPlacerRules, WeakDirectionsKeepThePrediction) {
  const Vector3d axis = Vector3d(1, 1, 0).normalized();
  Matrix6d covariance = Matrix6d::Identity() * 1e-6;
  covariance.topLeftCorner<3, 3>() += 0.09 * axis * axis.transpose();  // σ 0.3 m along it
  Isometry3d registered = Isometry3d::Identity(), predicted = Isometry3d::Identity();
  registered.translation() = Vector3d(1.0, 0.2, 0.1);
  predicted.translation() = Vector3d(0.0, 0.0, 0.0);
  Isometry3d kept = registered;
  EXPECT_EQ(tracking::keepPredictionAlongWeakDirections(kept, predicted, covariance, 0.1), 1);
  const Vector3d d = kept.translation() - predicted.translation();
  EXPECT_NEAR(d.dot(axis), 0.0, 1e-12);  // along the axis: the prediction
  const Vector3d across = registered.translation() - axis * registered.translation().dot(axis);
  EXPECT_LT((kept.translation() - across).norm(), 1e-12);  // across it: the registration
  Isometry3d tight = registered;
  EXPECT_EQ(tracking::keepPredictionAlongWeakDirections(tight, predicted, covariance, 0.5), 0);
  EXPECT_TRUE(tight.isApprox(registered));
}

// A pose from the last pose or the search replaces the prediction's, refused only by the
// free-space check, only if it fits the map's Gaussians no worse: score and matched share of
// the scan both at least the refused one's (the figures of a sparse lidar's corner, where the
// search found a pose 1.7 m off).
TEST(ScanPlacerRules, ARecoveryFittingLessThanTheRefusedPoseIsNotTaken) {
  const auto result = [](double score, double matched, double judged) {
    RegistrationResult r;
    r.score = score;
    r.matched_fraction = matched;
    r.judged_fraction = judged;
    r.converged = true;
    return r;
  };
  const std::optional<RegistrationResult> refused = result(0.1349, 0.83, 0.83);
  RegistrationResult escaped = result(0.1242, 0.92, 0.67);  // matched more of less judged
  EXPECT_FALSE(tracking::replacesRefused(escaped, refused, "the search's"));
  EXPECT_FALSE(escaped.converged);
  EXPECT_NE(escaped.failure.find("the search's pose fits the map less"), std::string::npos);
  EXPECT_NE(escaped.failure.find("0.1349"), std::string::npos) << escaped.failure;
  RegistrationResult higher_score = result(0.14, 0.5, 0.8);  // a better score alone is not enough
  EXPECT_FALSE(tracking::replacesRefused(higher_score, refused, "the last pose's"));
  RegistrationResult lower_score = result(0.12, 0.95, 0.85);  // nor a larger matched share
  EXPECT_FALSE(tracking::replacesRefused(lower_score, refused, "the search's"));
  RegistrationResult better = result(0.14, 0.9, 0.8);
  EXPECT_TRUE(tracking::replacesRefused(better, refused, "the search's"));
  EXPECT_TRUE(better.converged);
  EXPECT_TRUE(better.failure.empty());
  RegistrationResult equal = *refused;
  EXPECT_TRUE(tracking::replacesRefused(equal, refused, "the search's"));
  EXPECT_TRUE(tracking::replacesRefused(escaped = result(0.01, 0.3, 0.2), std::nullopt, "x"));
}

#ifdef NDTOM_HAVE_WORLD
// A map of a drive through the procedural city (a scan every metre), and scans of a second
// drive of the same streets (other noise) predicted where the previous scan was, as when the
// motion is not known yet. Registered on every ground point, the rings of the map's scans
// hold some of them a metre back, where the street is a corridor (the stall); with the
// ground thinned, each is placed within centimetres of where it was taken.
TEST(ScanPlacer, GroundRingsDoNotHoldAMovingScanWhereTheLastOneWas) {
  world::CityLayout layout;
  layout.blocks_x = layout.blocks_y = 3;
  const world::CityWorld city(layout);
  world::LidarModel lidar;
  lidar.rings = 16;
  lidar.azimuth_steps = 360;
  lidar.max_range = 30;
  world::RouteSettings route;
  route.length = 60;
  route.step = 1;
  const auto poses = world::driveThrough(city, route);
  const Eigen::Translation3d raise(0, 0, 0.2);  // the ground off the cell boundaries
  MapOptions options;
  options.resolution = 0.2;
  NdtMap map(options);
  for (size_t i = 0; i < poses.size(); ++i) {
    auto points = world::simulateScan(city, lidar, poses[i], i);
    for (auto& p : points) p = raise * (poses[i] * p);
    map.insertScan(points, raise * poses[i].translation());
  }
  lidar.seed = 2;
  const auto errorsWith = [&](int ground_thinning) {
    PlacementOptions o;
    o.ground_thinning = ground_thinning;
    ScanPlacer placer(o);
    std::vector<double> errors;
    for (size_t i = 10; i < poses.size() - 10; i += 4) {
      const Isometry3d truth = raise * poses[i], last = raise * poses[i - 1];
      const Placement p =
          placer.place(map, world::simulateScan(city, lidar, poses[i], i), last, last);
      errors.push_back(p.outcome == PlacementOutcome::Lost
                           ? 1e9
                           : (p.pose.translation() - truth.translation()).norm());
    }
    return errors;
  };
  const std::vector<double> thinned = errorsWith(100), all = errorsWith(1);
  size_t stalled = 0;
  for (size_t k = 0; k < thinned.size(); ++k) {
    EXPECT_LT(thinned[k], 0.05) << "scan " << 10 + 4 * k;
    stalled += all[k] > 0.5;
  }
  EXPECT_GE(stalled, 2u) << "the stall this rule is for did not happen";  // 2 of 11 here
}

// Online mapping (the map is the scans' own) of a drive through the city, a scan every metre.
std::vector<OnlineStep> mapOnline(const world::LidarModel& lidar, bool retry_without_finest,
                                  size_t scans, std::vector<Isometry3d>& truth) {
  world::CityLayout layout;
  layout.blocks_x = layout.blocks_y = 3;
  const world::CityWorld city(layout);
  world::RouteSettings route;
  route.length = double(scans);
  route.step = 1;
  truth = world::driveThrough(city, route);
  truth.resize(std::min(truth.size(), scans));
  OnlineMapperOptions o;
  o.map.scan.max_range = 30;
  o.placement.retry_without_finest = retry_without_finest;
  OnlineMapper mapper(o, truth[0]);
  std::vector<OnlineStep> steps;
  for (size_t i = 0; i < truth.size(); ++i)
    steps.push_back(mapper.process(world::simulateScan(city, lidar, truth[i], i), Vector3d::Zero(),
                                   0.1 * double(i)));
  return steps;
}

double positionError(const OnlineStep& step, const Isometry3d& truth) {
  return (step.pose.translation() - truth.translation()).norm();
}

// A sparse lidar (32 rings x 450 steps) on 0.2 m cells. Against the map of the first scan
// the finest level (0.4 m) matches the second too little to place it: lost, it leaves the
// map one scan, and every later scan is lost the same way. Tried without the finest level
// (0.8 m) it is placed; the map fills in, and the whole pyramid places the next scans.
TEST(ScanPlacer, ASparseScanTheFinestLevelCannotPlaceIsPlacedWithoutIt) {
  world::LidarModel sparse;
  sparse.azimuth_steps = 450;
  sparse.max_range = 40;
  std::vector<Isometry3d> truth;
  const std::vector<OnlineStep> without_retry = mapOnline(sparse, false, 30, truth);
  size_t lost = 0;
  for (const OnlineStep& s : without_retry) lost += s.outcome == OnlineOutcome::Lost;
  EXPECT_GE(lost, 25u) << "the failure this is for did not happen";

  const std::vector<OnlineStep> steps = mapOnline(sparse, true, 30, truth);
  size_t retried = 0, on_the_finest = 0, lost_now = 0;
  for (size_t i = 1; i < steps.size(); ++i) {
    const OnlineStep& s = steps[i];
    if (s.outcome == OnlineOutcome::Lost) {  // (one, where the street holds it loosely)
      ++lost_now;
      continue;
    }
    EXPECT_LT(positionError(s, truth[i]), 0.3) << "scan " << i;
    ASSERT_FALSE(s.registration.levels.empty());
    EXPECT_DOUBLE_EQ(s.registration.levels.back().resolution, s.without_finest ? 0.8 : 0.4);
    retried += s.without_finest;
    on_the_finest += !s.without_finest;
  }
  EXPECT_LE(lost_now, 2u);
  EXPECT_TRUE(steps[1].without_finest);
  EXPECT_GE(on_the_finest, 20u);  // the level is not given up
  EXPECT_LE(retried, 5u);
}

// The lidar the city drives use (32 x 900): every scan placed on the whole pyramid, none by
// the retry. (Before a level could start from the guess, the 3.2 m level pulled scan 11
// 1.6 m back along the street, the finer levels held it 1 m off, the free-space verdict
// refused it, and every later scan was lost; now three scans pass there 0.16 m off.)
TEST(ScanPlacer, ALidarTheFinestLevelSuitsIsPlacedOnIt) {
  world::LidarModel lidar;
  lidar.max_range = 40;
  std::vector<Isometry3d> truth;
  const std::vector<OnlineStep> steps = mapOnline(lidar, true, 30, truth);
  std::vector<double> errors;
  for (size_t i = 1; i < steps.size(); ++i) {
    ASSERT_NE(steps[i].outcome, OnlineOutcome::Lost) << "scan " << i;
    EXPECT_FALSE(steps[i].without_finest) << "scan " << i;
    errors.push_back(positionError(steps[i], truth[i]));
    EXPECT_LT(errors.back(), 0.25) << "scan " << i;
  }
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  EXPECT_LT(errors[errors.size() / 2], 0.02);
}

// A sparse lidar (32 x 450) round one block (ndtom-worldgen --km 0.34 --blocks 1
// --azimuth-steps 450). At the first corner the side street's walls, seen edge-on before, lie
// where grazing rays cleared the map: the free-space check refuses scans 148-153 at poses that
// are right. The search around the prediction then found one 1.7 m off that passed the check
// by turning the scan towards space the map had not seen (judged 0.67 against 0.83), and the
// drive went on from there. Such a pose fits the map's Gaussians less than the refused one, so
// it is not taken; and as the refused poses agree with the prediction, the online mapper
// places those scans (free_space_overrule), whose rays then correct the map's free space.
TEST(ScanPlacer, AtACornerGrazingRaysClearedNoScanIsPlacedFarOff) {
  world::CityLayout layout;
  layout.blocks_x = layout.blocks_y = 1;
  const world::CityWorld city(layout);
  world::RouteSettings route;
  route.length = 340;
  route.step = 1;
  std::vector<Isometry3d> truth = world::driveThrough(city, route);
  truth.resize(160);
  world::LidarModel lidar;
  lidar.azimuth_steps = 450;
  for (const double overrule : {0.0, OnlineMapperOptions().free_space_overrule}) {
    OnlineMapperOptions o;
    o.map.resolution = 0.2;
    o.map.scan.max_range = 30;
    o.free_space_overrule = overrule;
    OnlineMapper mapper(o);  // in the first scan's frame, as ndtom-slam
    size_t refused = 0, overruled = 0, lost = 0;
    for (size_t i = 0; i < truth.size(); ++i) {
      std::vector<Vector3d> scan = world::simulateScan(city, lidar, truth[i], i);
      for (Vector3d& p : scan) p = p.cast<float>().cast<double>();  // as ndtom-worldgen's files
      const OnlineStep s = mapper.process(scan, Vector3d::Zero(), 0.1 * double(i));
      refused += s.pose_from_refused_registration;
      overruled += s.free_space_overruled;
      lost += s.outcome == OnlineOutcome::Lost;
      // Odometry drifts 0.2 m by the corner; the pose the search found was 1.9 m off.
      const double error = positionError(s, truth[0].inverse() * truth[i]);
      EXPECT_LT(error, 0.6) << "overrule " << overrule << ": scan " << i << " ("
                            << toString(s.outcome) << ", " << s.found_by << ")";
    }
    if (overrule == 0) {
      EXPECT_GE(refused, 2u) << "the corner this is for did not happen";
      EXPECT_EQ(overruled, 0u);
    } else {
      EXPECT_GE(overruled, 1u);
      EXPECT_EQ(lost, 0u);
    }
  }
}

#endif

}  // namespace

// Issue #38: --recovery-radius 100 --search-step 0.1 (each in its range) made a search of
// 9.4 million poses per lost scan; refused before any scan, naming the option.
TEST(ScanPlacerRules, ARecoverySearchPastThePoseLimitIsRefusedUpFront) {
  PlacementOptions o;
  EXPECT_NO_THROW(validate(o));
  o.recovery_radius = 100;
  o.search.position_step = 0.1;
  try {
    validate(o);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("recovery_radius", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("poses"), std::string::npos) << e.what();
  }
  o.recovery_yaw_deg = 0;  // one yaw, 785k x, y points on the 0.1 m grid: within the limit
  o.recovery_radius = 50;
  EXPECT_LE(searchAroundPoses(o.search, o.recovery_radius, 0), kMaxSearchPoses);
  EXPECT_NO_THROW(validate(o));
}
