// NdtRegistration end to end: known motions of synthetic scans, real lidar scans against
// their reference poses (the shipped BALM subset), the verdict on scans that cannot match,
// thread-count independence, the pyramid cache, and bad input.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <random>

#include "core/synthetic_room.h"
#include "ndtom/map/memory_budget.h"
#include "ndtom/registration/map_pyramid.h"
#include "ndtom/registration/registration.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

using namespace ndtom;
namespace room = ndtom::testing;
using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace {

const double kDeg = M_PI / 180;
const std::string kBalm = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld";

Isometry3d poseOf(const Vector3d& t, double angle, const Vector3d& axis) {
  Isometry3d p = Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  p.translation() = t;
  return p;
}

double translationError(const Isometry3d& a, const Isometry3d& b) {
  return (a.translation() - b.translation()).norm();
}
double rotationErrorDeg(const Isometry3d& a, const Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() / kDeg;
}

// `world` points as the sensor at `pose` sees them.
std::vector<Vector3d> inSensorFrame(const std::vector<Vector3d>& world, const Isometry3d& pose) {
  std::vector<Vector3d> out;
  for (const Vector3d& p : world) out.push_back(pose.inverse() * p);
  return out;
}

// A noise-free room map and a noise-free scan of other samples of the same surfaces: the
// score's maximum is the true pose, up to the sampling of the cells.
struct SyntheticCase {
  NdtMap map;
  Isometry3d truth = poseOf(room::kRoomSensor, 0, Vector3d::UnitZ());
  std::vector<Vector3d> scan;

  SyntheticCase() : map(makeMap()) {
    truth = poseOf(Vector3d(0.4, -0.3, 1.2), 7 * kDeg, Vector3d(0.2, -0.1, 1));
    scan = inSensorFrame(room::sampleRoom(40000, 21, 0.0), truth);
  }
  static NdtMap makeMap() {
    MapOptions o;
    o.resolution = 0.2;
    o.regularization.min_eigen_ratio = 1e-4;
    NdtMap m(o);
    m.insertScan(room::sampleRoom(400000, 1, 0.0), room::kRoomSensor);
    return m;
  }
};

struct RealCase {
  NdtMap map;
  std::vector<Isometry3d> poses;
  std::vector<Vector3d> scan;  // scan kLeftOut, sensor frame, not in the map
  static constexpr int kLeftOut = 5;

  RealCase() : map(mapOptions()) {
    for (const auto& p : io::readPoseFile(kBalm + "/poses.txt")) poses.push_back(p.pose);
    for (int i = 0; i < 10; ++i) {
      const auto cloud = io::readPcd(kBalm + "/full" + std::to_string(i) + ".pcd");
      std::vector<Vector3d> sensor;
      for (const Vector3d& p : cloud.points)
        if (p.allFinite() && p.norm() > 0.5) sensor.push_back(p);
      if (i == kLeftOut) {
        scan = sensor;
        continue;
      }
      std::vector<Vector3d> world;
      for (const Vector3d& p : sensor) world.push_back(poses[i] * p);
      map.insertScan(world, poses[i].translation());
    }
  }
  static MapOptions mapOptions() {
    MapOptions o;
    o.resolution = 0.2;
    o.scan.max_range = 30;
    return o;
  }
};

const RealCase& realCase() {
  static const RealCase c;
  return c;
}

}  // namespace

TEST(Registration, RecoversAKnownMotionOfASyntheticScan) {
  const SyntheticCase c;
  for (const auto method : {RegistrationMethod::P2D, RegistrationMethod::D2D}) {
    RegistrationOptions o;
    o.method = method;
    o.level_factors = {4, 2, 1};
    o.max_points = 40000;
    o.translation_epsilon = 1e-6;
    o.rotation_epsilon = 1e-6;
    NdtRegistration registration(o);
    const Isometry3d guess =
        c.truth * poseOf(Vector3d(0.25, -0.2, 0.1), 4 * kDeg, Vector3d(1, 1, 3));
    const RegistrationResult r = registration.align(c.map, c.scan, guess);
    EXPECT_TRUE(r.converged) << toString(method) << ": " << r.failure;
    EXPECT_LT(translationError(r.pose, c.truth), 1e-4) << toString(method);
    EXPECT_LT(rotationErrorDeg(r.pose, c.truth), 1e-3) << toString(method);
    EXPECT_GT(r.matched_fraction, 0.95) << toString(method);
  }
}

TEST(Registration, RealScanComesBackToItsReferencePose) {
  const RealCase& c = realCase();
  const Isometry3d& truth = c.poses[RealCase::kLeftOut];
  for (const auto method : {RegistrationMethod::P2D, RegistrationMethod::D2D}) {
    RegistrationOptions o;
    o.method = method;
    NdtRegistration registration(o);
    for (const auto& [offset, angle] : {std::pair{Vector3d(1.0, -0.5, 0.1), 10 * kDeg},
                                        std::pair{Vector3d(-2.0, 1.0, 0.0), -20 * kDeg}}) {
      Isometry3d guess = truth;
      guess.translation() += offset;
      guess.linear() = Eigen::AngleAxisd(angle, Vector3d::UnitZ()) * truth.linear();
      const RegistrationResult r = registration.align(c.map, c.scan, guess);
      EXPECT_TRUE(r.converged) << toString(method) << ": " << r.failure;
      EXPECT_LT(translationError(r.pose, truth), 0.02) << toString(method);
      EXPECT_LT(rotationErrorDeg(r.pose, truth), 0.2) << toString(method);
      ASSERT_EQ(r.levels.size(), 5u);
      EXPECT_DOUBLE_EQ(r.levels.back().resolution, 0.2);
      EXPECT_DOUBLE_EQ(r.levels.front().resolution, 3.2);
      // The reported spread covers the error to the reference within a few sigma, and is
      // not absurdly loose either.
      EXPECT_LT((r.covariance.topLeftCorner<3, 3>().trace()), 0.01);
      EXPECT_GT((r.covariance.topLeftCorner<3, 3>().trace()), 0);
    }
  }
}

TEST(Registration, ScanFarFromTheMapIsReportedAsFailed) {
  const RealCase& c = realCase();
  for (const auto method : {RegistrationMethod::P2D, RegistrationMethod::D2D}) {
    RegistrationOptions o;
    o.method = method;
    NdtRegistration registration(o);
    // 300 m away, or inside the map but turned 180° about a vertical axis.
    Isometry3d far = c.poses[RealCase::kLeftOut];
    far.translation() += Vector3d(300, 0, 0);
    Isometry3d turned = c.poses[RealCase::kLeftOut];
    turned.linear() = Eigen::AngleAxisd(M_PI, Vector3d::UnitZ()) * turned.linear();
    for (const Isometry3d& guess : {far, turned}) {
      const RegistrationResult r = registration.align(c.map, c.scan, guess);
      const bool right = translationError(r.pose, c.poses[RealCase::kLeftOut]) < 0.1 &&
                         rotationErrorDeg(r.pose, c.poses[RealCase::kLeftOut]) < 1;
      EXPECT_TRUE(right || !r.converged) << toString(method) << ": a wrong pose reported good";
      EXPECT_EQ(r.converged, r.failure.empty());
    }
  }
}

TEST(Registration, PlanarChangesOnlyXYAndYaw) {
  const RealCase& c = realCase();
  const Isometry3d& truth = c.poses[RealCase::kLeftOut];
  RegistrationOptions o;
  o.planar = true;
  NdtRegistration registration(o);
  Isometry3d guess = truth;
  guess.translation() += Vector3d(0.8, -0.6, 0);  // planar: z, roll and pitch are known
  guess.linear() = Eigen::AngleAxisd(8 * kDeg, Vector3d::UnitZ()) * truth.linear();
  const RegistrationResult r = registration.align(c.map, c.scan, guess);
  EXPECT_TRUE(r.converged) << r.failure;
  EXPECT_LT((r.pose.translation() - truth.translation()).head<2>().norm(), 0.02);
  EXPECT_EQ(r.pose.translation().z(), guess.translation().z());
  // The sensor's axes turned about z only: its z axis, and so roll and pitch, as guessed.
  EXPECT_TRUE(r.pose.linear().row(2).isApprox(guess.linear().row(2), 1e-12));
  EXPECT_LT(rotationErrorDeg(r.pose, truth), 0.2);
  for (int k : {2, 3, 4}) {
    EXPECT_EQ(r.covariance.row(k).norm(), 0);
    EXPECT_EQ(r.covariance.col(k).norm(), 0);
  }
  EXPECT_GT(r.covariance(0, 0), 0);
  EXPECT_GT(r.covariance(5, 5), 0);
}

// The complement: x, y and yaw as guessed (right), z, roll and pitch found.
TEST(Registration, LevelOnlyChangesOnlyZRollAndPitch) {
  const RealCase& c = realCase();
  const Isometry3d& truth = c.poses[RealCase::kLeftOut];
  RegistrationOptions o;
  o.level_only = true;
  NdtRegistration registration(o);
  Isometry3d guess = truth;
  guess.translation().z() += 0.3;
  guess.linear() = Eigen::AngleAxisd(2 * kDeg, Vector3d(1, 1, 0).normalized()) * truth.linear();
  const RegistrationResult r = registration.align(c.map, c.scan, guess);
  EXPECT_TRUE(r.converged) << r.failure;
  EXPECT_LT(translationError(r.pose, truth), 0.02);
  EXPECT_LT(rotationErrorDeg(r.pose, truth), 0.2);
  EXPECT_EQ(r.pose.translation().head<2>(), guess.translation().head<2>());
  // The heading, the sensor's x axis projected on the ground, turned not at all.
  const Vector3d heading = r.pose.linear().col(0), guessed = guess.linear().col(0);
  EXPECT_NEAR(std::atan2(heading.y(), heading.x()), std::atan2(guessed.y(), guessed.x()), 1e-3);
  for (int k : {0, 1, 5}) {
    EXPECT_EQ(r.covariance.row(k).norm(), 0);
    EXPECT_EQ(r.covariance.col(k).norm(), 0);
  }
  EXPECT_GT(r.covariance(2, 2), 0);
  RegistrationOptions both = o;
  both.planar = true;
  EXPECT_THROW(NdtRegistration{both}, std::invalid_argument);
}

TEST(Registration, SameResultForOneAndTwoThreads) {
  const RealCase& c = realCase();
  Isometry3d guess = c.poses[RealCase::kLeftOut];
  guess.translation() += Vector3d(0.7, 0.4, 0);
  for (const auto method : {RegistrationMethod::P2D, RegistrationMethod::D2D}) {
    RegistrationOptions o;
    o.method = method;
    NdtRegistration one(o);
    const RegistrationResult a = one.align(c.map, c.scan, guess);
    for (const int threads : {2, 3}) {
      SCOPED_TRACE(std::string(toString(method)) + ", threads " + std::to_string(threads));
      o.threads = threads;
      NdtRegistration many(o);
      const RegistrationResult b = many.align(c.map, c.scan, guess);
      EXPECT_EQ(a.pose.matrix(), b.pose.matrix());
      EXPECT_EQ(a.covariance, b.covariance);
      EXPECT_EQ(a.score, b.score);
      EXPECT_EQ(a.free_fraction, b.free_fraction);
      EXPECT_EQ(a.judged_fraction, b.judged_fraction);
      EXPECT_EQ(a.matched_fraction, b.matched_fraction);
      ASSERT_EQ(a.levels.size(), b.levels.size());
      for (size_t l = 0; l < a.levels.size(); ++l)
        EXPECT_EQ(a.levels[l].iterations, b.levels[l].iterations);
    }
  }
}

TEST(Registration, PyramidIsKeptUntilTheMapChanges) {
  NdtMap map = room::roomMap(0.2, 60000);
  const auto scan =
      inSensorFrame(room::sampleRoom(5000, 4), poseOf(room::kRoomSensor, 0, Vector3d::UnitZ()));
  NdtRegistration registration;
  const Isometry3d guess = poseOf(room::kRoomSensor, 0, Vector3d::UnitZ());
  EXPECT_TRUE(registration.align(map, scan, guess).pyramid_rebuilt);
  const auto first = registration.pyramid();
  EXPECT_FALSE(registration.align(map, scan, guess).pyramid_rebuilt);
  EXPECT_EQ(first, registration.pyramid());
  const NdtMap copy = map;  // same contents, same revision
  EXPECT_FALSE(registration.align(copy, scan, guess).pyramid_rebuilt);
  map.insertScan(room::sampleRoom(100, 9), room::kRoomSensor);
  EXPECT_TRUE(registration.align(map, scan, guess).pyramid_rebuilt);
  EXPECT_NE(first, registration.pyramid());
}

// The levels are built from the cells with statistics only, on several threads: they must be
// the occupied Gaussians of the coarsened map (all its cells, free ones too), bit for bit.
// A pinned pyramid (an online mapper's region of the map) is used while the map keeps the
// revision it was pinned for: the map may grow without a rebuild until then.
TEST(Registration, APinnedPyramidIsUsedForItsRevision) {
  const SyntheticCase c;
  RegistrationOptions o;
  o.level_factors = {4, 2, 1};
  NdtRegistration registration(o);
  NdtMap grown = c.map;
  grown.insertScan(room::sampleRoom(2000, 5, 0.0), room::kRoomSensor);
  const auto pinned = std::make_shared<const MapPyramid>(c.map, o.level_factors);
  registration.pinPyramid(pinned, grown.revision());
  const Isometry3d guess = c.truth * poseOf(Vector3d(0.1, 0, 0), 0, Vector3d::UnitZ());
  const RegistrationResult r = registration.align(grown, c.scan, guess);
  EXPECT_EQ(registration.pyramid(), pinned);
  EXPECT_TRUE(r.converged) << r.failure;
  grown.insertScan(room::sampleRoom(100, 6, 0.0), room::kRoomSensor);  // a new revision
  registration.align(grown, c.scan, guess);
  EXPECT_NE(registration.pyramid(), pinned);
  EXPECT_THROW(
      registration.pinPyramid(std::make_shared<const MapPyramid>(c.map, std::vector<int>{2, 1}), 1),
      std::invalid_argument);
}

TEST(Registration, PyramidLevelsHoldTheOccupiedGaussiansOfTheCoarsenedMap) {
  for (const bool occupancy : {true, false}) {
    MapOptions o;
    o.resolution = 0.2;
    o.occupancy.enabled = occupancy;
    NdtMap map(o);
    map.insertScan(room::sampleRoom(60000, 1, 0.01), room::kRoomSensor);
    map.insertScan(room::sampleRoom(30000, 2, 0.01), room::kRoomSensor + Vector3d(0.7, -0.4, 0.1));
    for (const int threads : {1, 3}) {
      const MapPyramid pyramid(map, {8, 4, 2, 1}, threads);
      ASSERT_EQ(pyramid.size(), 4u);
      for (size_t l = 0; l < pyramid.size(); ++l) {
        const NdtMap coarse = map.coarsened(pyramid.factor(l));
        const GaussianLookup expected(coarse, {/*occupied_only=*/true, /*nearest_means=*/false});
        ASSERT_EQ(pyramid.level(l).size(), expected.size()) << occupancy << " " << l;
        ASSERT_GT(expected.size(), 10u);
        std::vector<const PreparedGaussian*> got, want;
        pyramid.level(l).forEachGaussian([&](const PreparedGaussian& g) { got.push_back(&g); });
        expected.forEachGaussian([&](const PreparedGaussian& g) { want.push_back(&g); });
        for (size_t i = 0; i < expected.size(); ++i) {
          const PreparedGaussian &a = *got[i], &b = *want[i];
          EXPECT_EQ(a.cell, b.cell);
          EXPECT_EQ(a.n, b.n);
          EXPECT_EQ(std::memcmp(a.mean.data(), b.mean.data(), sizeof(double) * 3), 0);
          EXPECT_EQ(std::memcmp(a.information.data(), b.information.data(), sizeof(double) * 9), 0);
        }
        EXPECT_DOUBLE_EQ(pyramid.resolution(l), 0.2 * pyramid.factor(l));
      }
    }
  }
  const NdtMap map = room::roomMap(0.2, 60000);
  EXPECT_THROW(MapPyramid(map, {1, 2}), std::invalid_argument);
  EXPECT_THROW(MapPyramid(map, {}), std::invalid_argument);
}

TEST(Registration, FreeSpaceAttractsNothing) {
  // A wall seen once and then swept by many rays: its cells become free and lose their
  // Gaussians, so a scan of that wall has nothing to match.
  MapOptions o;
  o.resolution = 0.2;
  NdtMap map(o);
  std::vector<Vector3d> wall, behind;
  for (int i = 0; i < 80; ++i)
    for (int j = 0; j < 40; ++j) {
      if (i < 40 && j < 20) wall.emplace_back(3.0, -1.95 + 0.1 * i, 0.05 + 0.1 * j);
      behind.emplace_back(6.0, -3.95 + 0.1 * i, 0.05 + 0.1 * j);  // its rays cross the wall
    }
  map.insertScan(wall, Vector3d::Zero());
  for (int k = 0; k < 200; ++k) map.insertScan(behind, Vector3d::Zero());
  RegistrationOptions ro;
  ro.level_factors = {1};  // the wall behind is 15 cells away: out of reach
  NdtRegistration registration(ro);
  const RegistrationResult r = registration.align(map, wall, Isometry3d::Identity());
  EXPECT_EQ(r.matched_fraction, 0.0);
  EXPECT_FALSE(r.converged);
  EXPECT_TRUE(r.pose.isApprox(Isometry3d::Identity()));
  const GaussianLookup& level = registration.pyramid()->level(0);
  for (const Vector3d& p : wall) EXPECT_EQ(level.find(map.geometry().cellOf(p)), nullptr);
  EXPECT_NE(level.find(map.geometry().cellOf(behind[100])), nullptr);
}

// The map of scans 0-4 seen only through a 100° wedge in front of the sensor: most of scan 5
// lands where that map has never looked. Those points are neither matches nor misses, so the
// scan is placed, and the verdict says how little of it the map could judge; without
// occupancy a map cannot tell never-seen from free, and the same scan fails.
TEST(Registration, ScanSeeingTheMapInPartIsPlacedByWhatTheMapKnows) {
  const RealCase& full = realCase();
  const Isometry3d& truth = full.poses[RealCase::kLeftOut];
  for (const bool occupancy : {true, false}) {
    MapOptions mo = RealCase::mapOptions();
    mo.occupancy.enabled = occupancy;
    NdtMap wedge(mo);
    for (int i = 0; i < RealCase::kLeftOut; ++i) {
      const auto cloud = io::readPcd(kBalm + "/full" + std::to_string(i) + ".pcd");
      std::vector<Vector3d> world;
      for (const Vector3d& p : cloud.points)
        if (p.allFinite() && p.norm() > 0.5 && std::abs(std::atan2(p.y(), p.x())) < 50 * kDeg)
          world.push_back(full.poses[i] * p);
      wedge.insertScan(world, full.poses[i].translation());
    }
    NdtRegistration registration;
    const Isometry3d guess = truth * poseOf(Vector3d(0.3, -0.2, 0.05), 3 * kDeg, Vector3d::UnitZ());
    const RegistrationResult r = registration.align(wedge, full.scan, guess);
    if (occupancy) {
      EXPECT_TRUE(r.converged) << r.failure;
      EXPECT_LT(translationError(r.pose, truth), 0.05);
      EXPECT_LT(r.judged_fraction, 0.6);
      EXPECT_GT(r.judged_fraction, 0.15);
      EXPECT_GT(r.matched_fraction, 0.6);
      // Asked to judge most of the scan, the same map cannot.
      RegistrationOptions strict;
      strict.min_judged_fraction = 0.9;
      registration.setOptions(strict);
      const RegistrationResult s = registration.align(wedge, full.scan, guess);
      EXPECT_FALSE(s.converged);
      EXPECT_NE(s.failure.find("min_judged_fraction"), std::string::npos) << s.failure;
    } else {
      EXPECT_EQ(r.judged_fraction, 1.0);
      EXPECT_LT(r.matched_fraction, 0.4);
      EXPECT_FALSE(r.converged);
    }
  }
}

// A sparse scan (a few points per square metre, as a 32-ring lidar's far surfaces) leaves most
// occupied cells with too few points for a Gaussian. Registered against its own map at its
// own pose, the points in those cells are not misses: the map cannot judge them.
TEST(Registration, OccupiedCellsWithoutAGaussianDoNotJudge) {
  MapOptions o;
  o.resolution = 0.2;
  NdtMap map(o);
  const std::vector<Vector3d> world = room::sampleRoom(4000, 3, 0.0);
  map.insertScan(world, room::kRoomSensor);
  size_t thin = 0, occupied = 0;
  map.forEachCell([&](const CellView& c) {
    if (c.logodds <= 0) return;
    ++occupied;
    thin += !(c.stats && c.stats->hasGaussian());
  });
  ASSERT_GT(thin, occupied / 2);  // mostly cells of one or two points
  const Isometry3d pose = poseOf(room::kRoomSensor, 0, Vector3d::UnitZ());
  RegistrationOptions ro;
  ro.max_points = 100000;
  NdtRegistration registration(ro);
  const RegistrationResult r = registration.align(map, inSensorFrame(world, pose), pose);
  EXPECT_TRUE(r.converged) << r.failure;
  EXPECT_LT(translationError(r.pose, pose), 0.05);
  EXPECT_LT(r.judged_fraction, 0.6);
  EXPECT_GT(r.matched_fraction, 0.6);
}

TEST(Registration, ScanPointsInOpenFreeSpaceFailTheVerdict) {
  // The room's map knows its inside is free. A scan of the room with points spread through
  // a 2 x 2 x 1 m volume in its middle (objects the map never had) still aligns; with 0.5 %
  // of its points there it is accepted, with 25 % the verdict names the free space.
  const NdtMap map = room::roomMap(0.2, 200000);
  const Isometry3d truth = poseOf(room::kRoomSensor, 0, Vector3d::UnitZ());
  for (const double share : {0.005, 0.25}) {
    std::vector<Vector3d> world = room::sampleRoom(20000, 8, 0.0);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(0, 1);
    const size_t floating = size_t(share / (1 - share) * double(world.size()));
    for (size_t i = 0; i < floating; ++i)
      world.emplace_back(-2.5 + 2 * u(rng), -1.5 + 2 * u(rng), 0.8 + u(rng));
    RegistrationOptions o;
    o.max_points = 100000;
    NdtRegistration registration(o);
    const RegistrationResult r =
        registration.align(map, inSensorFrame(world, truth),
                           truth * poseOf(Vector3d(0.05, 0, 0), 0, Vector3d::UnitZ()));
    EXPECT_LT(translationError(r.pose, truth), 0.01) << share;
    // (Fractions of the scan's voxels, not points: the floating points are spread thinner.)
    EXPECT_EQ(r.free_fraction < 0.03, share < 0.1) << share << ": " << r.free_fraction;
    EXPECT_EQ(r.converged, share < 0.1) << share << ": " << r.failure;
    if (!r.converged) {
      EXPECT_NE(r.failure.find("open space"), std::string::npos) << r.failure;
    }
  }
}

TEST(Registration, BadInputIsRejectedAndChangesNothing) {
  const NdtMap map = room::roomMap(0.2, 20000);
  const auto scan = room::sampleRoom(2000, 3);
  NdtRegistration registration;
  const Isometry3d guess = Isometry3d::Identity();

  EXPECT_THROW(registration.align(map, {}, guess), std::invalid_argument);
  const std::vector<Vector3d> nan_scan(10, Vector3d(NAN, 0, 0));
  EXPECT_THROW(registration.align(map, nan_scan, guess), std::invalid_argument);
  Isometry3d nan_guess = guess;
  nan_guess.translation().x() = NAN;
  EXPECT_THROW(registration.align(map, scan, nan_guess), std::invalid_argument);
  Isometry3d mirror = guess;
  mirror.linear()(0, 0) = -1;
  EXPECT_THROW(registration.align(map, scan, mirror), std::invalid_argument);
  EXPECT_THROW(registration.align(NdtMap(), scan, guess), std::invalid_argument);
  EXPECT_EQ(registration.pyramid(), nullptr);  // nothing cached by a failed call

  RegistrationOptions bad;
  bad.level_factors = {1, 2};
  EXPECT_THROW(NdtRegistration{bad}, std::invalid_argument);
  bad = RegistrationOptions{};
  bad.outlier_ratio = 1;
  EXPECT_THROW(registration.setOptions(bad), std::invalid_argument);
  bad = RegistrationOptions{};
  bad.threads = 0;
  EXPECT_THROW(registration.setOptions(bad), std::invalid_argument);
  EXPECT_EQ(registration.options().threads, 1);
  EXPECT_THROW(registrationMethodFromString("icp"), std::invalid_argument);
}

// Issue #38: the pyramid over a map of one Gaussian a block took 2.75 GB beside a 7.6 MB
// file. Its levels now count against the map's memory budget, beside the map.
TEST(MapPyramid, LevelsCountAgainstTheMapsMemoryBudget) {
  ndtom::MapOptions o;
  o.resolution = 0.2;
  o.occupancy.enabled = false;
  ndtom::NdtMap map(o);
  ndtom::CellStats stats;
  stats.n = 3;
  stats.scatter = Eigen::Matrix3d::Identity() * 0.001;
  for (int i = 0; i < 40; ++i)  // 3200 blocks 3.2 m apart: each level as large as the map
    for (int j = 0; j < 40; ++j)
      for (int k = 0; k < 2; ++k) map.setCell({16 * i, 16 * j, 16 * k}, 0.f, stats);
  const std::vector<int> factors{16, 8, 4, 2, 1};
  const ndtom::MapPyramid pyramid(map, factors);
  size_t levels_bytes = 0;
  for (size_t l = 0; l < pyramid.size(); ++l) {
    EXPECT_EQ(pyramid.level(l).size(), map.numGaussians()) << l;  // nothing merges
    levels_bytes += pyramid.level(l).memoryBytes();
  }
  EXPECT_LE(levels_bytes,
            factors.size() * map.numGaussians() * ndtom::GaussianLookup::maxBytesPerGaussian());
  // A budget the map fits in but not its levels: refused, naming the pyramid.
  ndtom::MapOptions tight = o;
  tight.scan.memory_budget = map.memoryBytes() + levels_bytes / 2;
  ndtom::NdtMap small(tight);
  map.forEachCell([&](const ndtom::CellView& c) { small.setCell(c.index, c.logodds, *c.stats); });
  try {
    const ndtom::MapPyramid refused(small, factors);
    ADD_FAILURE() << "built within " << tight.scan.memory_budget;
  } catch (const ndtom::MemoryBudgetError& e) {
    EXPECT_NE(std::string(e.what()).find("registration pyramid"), std::string::npos) << e.what();
  }
}
