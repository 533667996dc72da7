// The NdtMcl likelihood of CNDTOccupancyMap (likelihood_method = NdtMcl) on real lidar scans:
// - against the reference poses (BALM real world): a scan left out of the map scores best at
//   its pose among poses moved along and about each axis; on the shared 60-scan sequence
//   (skipped when absent) the same for scans the map of scans 0-29 never saw;
// - the adapter against the core: the observation's points in the robot frame (its sensor
//   pose applied) give the core's score exactly; the NDT is built once per observation;
// - bad input: no overlap with the map, empty and all-invalid scans, unsupported
//   observations give finite values (the floor, or 0 for no information), never a throw;
//   bad options set in code throw naming the option;
// - concurrent calls as pf-localization's repetitions make them agree with sequential ones.
#include <gtest/gtest.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationPointCloud.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <thread>

#include "balm_scans.h"
#include "mrpt_ndtom/CNDTOccupancyMap.h"

using mrpt::poses::CPose3D;
using mrpt_ndtom::CNDTOccupancyMap;
using ndtom::testing::toPose;

namespace {

constexpr double kDeg = M_PI / 180;

mrpt::obs::CObservationPointCloud::Ptr cloudObservation(mrpt::maps::CSimplePointsMap::Ptr points) {
  auto obs = mrpt::obs::CObservationPointCloud::Create();
  obs->pointcloud = std::move(points);
  return obs;
}

// Scans of a folder like tests/data/balm-realworld (fullN.pcd, poses.txt), without non-finite
// points and those within 0.5 m of the sensor (the platform).
mrpt::maps::CSimplePointsMap::Ptr scanOf(const std::string& folder, int i) {
  const auto cloud = ndtom::io::readPcd(folder + "/full" + std::to_string(i) + ".pcd");
  auto points = mrpt::maps::CSimplePointsMap::Create();
  for (const auto& p : cloud.points)
    if (p.allFinite() && p.norm() > 0.5) points->insertPoint(p.x(), p.y(), p.z());
  return points;
}

std::vector<CPose3D> posesOf(const std::string& folder) {
  std::vector<CPose3D> poses;
  for (const auto& p : ndtom::io::readPoseFile(folder + "/poses.txt"))
    poses.push_back(toPose(p.pose));
  return poses;
}

// A 0.2 m map as the filter's .ini makes it (rays cut at 30 m), NdtMcl likelihood.
CNDTOccupancyMap ndtMclMap() {
  CNDTOccupancyMap map(0.2);
  map.insertionOptions.scan.max_range = 30.0;
  map.likelihoodOptions.likelihood_method = CNDTOccupancyMap::TLikelihoodMethod::NdtMcl;
  map.likelihoodOptions.max_range = 30.0;
  return map;
}

// Offsets along and about each axis of the sensor (x, y, z, yaw, pitch, roll), both signs.
std::vector<CPose3D> offsets(double d, double a) {
  std::vector<CPose3D> out;
  for (const double s : {-1.0, 1.0}) {
    out.emplace_back(s * d, 0, 0, 0, 0, 0);
    out.emplace_back(0, s * d, 0, 0, 0, 0);
    out.emplace_back(0, 0, s * d, 0, 0, 0);
    out.emplace_back(0, 0, 0, s * a, 0, 0);
    out.emplace_back(0, 0, 0, 0, s * a, 0);
    out.emplace_back(0, 0, 0, 0, 0, s * a);
  }
  return out;
}

// Every offset scores below the pose; prints the margin.
void expectPeakAtThePose(const CNDTOccupancyMap& map, const mrpt::obs::CObservation& obs,
                         const CPose3D& pose, const std::string& what) {
  const double at_pose = map.computeObservationLikelihood(obs, pose);
  ASSERT_TRUE(std::isfinite(at_pose));
  double best = -INFINITY;
  for (const auto& [d, a] : {std::pair{0.1, 1.0}, std::pair{0.2, 3.0}, std::pair{0.5, 10.0}})
    for (const CPose3D& offset : offsets(d, a * kDeg)) {
      const double moved = map.computeObservationLikelihood(obs, pose + offset);
      EXPECT_LT(moved, at_pose) << what << ", offset " << offset.asString();
      best = std::max(best, moved);
    }
  std::cout << "[ ndt-mcl  ] " << what << ": log-likelihood " << at_pose
            << " at the pose, best of 36 offsets " << best << " ("
            << map.scanNdt(obs)->gaussians.size() << " scan Gaussians)\n";
}

}  // namespace

TEST(LikelihoodNdtMcl, TruePoseBeatsOffsetsOnTheShippedScans) {
  const std::vector<CPose3D> poses = ndtom::testing::balmPoses();
  ASSERT_EQ(poses.size(), 10u);
  for (const int held_out : {1, 5, 8}) {
    CNDTOccupancyMap map = ndtMclMap();
    for (int i = 0; i < 10; ++i)
      if (i != held_out) {
        ASSERT_TRUE(
            map.insertObservation(*cloudObservation(ndtom::testing::balmScan(i)), poses[i]));
      }
    const auto obs = cloudObservation(ndtom::testing::balmScan(held_out));
    expectPeakAtThePose(map, *obs, poses[held_out], "shipped scan " + std::to_string(held_out));
  }
}

TEST(LikelihoodNdtMcl, TruePoseBeatsOffsetsOnScansTheMapNeverSaw) {
  const std::string folder = std::string(NDTOM_SHARED_DATASETS) + "/balm-realworld";
  if (!std::filesystem::exists(folder + "/full59.pcd"))
    GTEST_SKIP() << "needs the shared 60-scan sequence at " << folder;
  const std::vector<CPose3D> poses = posesOf(folder);
  CNDTOccupancyMap map = ndtMclMap();
  for (int i = 0; i < 30; ++i)
    ASSERT_TRUE(map.insertObservation(*cloudObservation(scanOf(folder, i)), poses[size_t(i)]));
  // Up to 9 m from where the map's scans were taken, turned by up to 150°.
  for (const int i : {35, 45, 55})
    expectPeakAtThePose(map, *cloudObservation(scanOf(folder, i)), poses[size_t(i)],
                        "shared scan " + std::to_string(i));
}

TEST(LikelihoodNdtMcl, EqualsTheCoreOnTheRobotFramePoints) {
  const std::vector<CPose3D> poses = ndtom::testing::balmPoses();
  CNDTOccupancyMap map = ndtMclMap();
  map.likelihoodOptions.scale = 0.3;
  map.likelihoodOptions.outlier_likelihood = 0.1;
  map.likelihoodOptions.min_range = 1.0;
  map.likelihoodOptions.ndt_mcl_scan_factor = 3;
  map.likelihoodOptions.ndt_mcl_map_factor = 2;
  for (int i = 0; i < 4; ++i)
    map.insertObservation(*cloudObservation(ndtom::testing::balmScan(i)), poses[size_t(i)]);

  // The sensor sits 0.3 m up and tilted on the robot: the observation's points are in the
  // sensor frame, the NDT must be built in the robot frame.
  const CPose3D sensor_on_robot(0.1, -0.05, 0.3, 10 * kDeg, -5 * kDeg, 3 * kDeg);
  const CPose3D robot = poses[5] + (-sensor_on_robot);
  auto obs = cloudObservation(ndtom::testing::balmScan(5));
  obs->sensorPose = sensor_on_robot;

  // Oracle: the core, on the points moved to the robot frame by MRPT's own composePoint and
  // kept between min_range and max_range from the sensor.
  std::vector<Eigen::Vector3d> robot_points;
  const auto& xs = obs->pointcloud->getPointsBufferRef_x();
  const auto& ys = obs->pointcloud->getPointsBufferRef_y();
  const auto& zs = obs->pointcloud->getPointsBufferRef_z();
  for (size_t k = 0; k < xs.size(); ++k) {
    const double range =
        std::sqrt(double(xs[k]) * xs[k] + double(ys[k]) * ys[k] + double(zs[k]) * zs[k]);
    if (range < 1.0 || range > 30.0) continue;
    double x, y, z;
    sensor_on_robot.composePoint(xs[k], ys[k], zs[k], x, y, z);
    robot_points.emplace_back(x, y, z);
  }
  ndtom::ScanNdtOptions scan_options;
  scan_options.cell_size = 0.6;
  const ndtom::ScanNdt scan = ndtom::buildScanNdt(robot_points, scan_options);
  const ndtom::NdtMclMap level(map.ndtMap().coarsened(2));
  ndtom::NdtMclOptions core;
  core.outlier_likelihood = 0.1;
  ASSERT_EQ(scan.gaussians.size(), 300u);

  for (const CPose3D& offset : offsets(0.3, 4 * kDeg)) {
    const CPose3D at = robot + offset;
    const double expected =
        0.3 * ndtom::ndtMclLikelihood(level, scan, mrpt_ndtom::toIsometry(at), core).log_likelihood;
    EXPECT_NEAR(map.computeObservationLikelihood(*obs, at), expected, 1e-9 * std::abs(expected));
  }
}

TEST(LikelihoodNdtMcl, TheScanNdtIsBuiltOncePerObservation) {
  const std::vector<CPose3D> poses = ndtom::testing::balmPoses();
  CNDTOccupancyMap map = ndtMclMap();
  map.insertObservation(*cloudObservation(ndtom::testing::balmScan(0)), poses[0]);
  const auto a = cloudObservation(ndtom::testing::balmScan(1));
  const auto b = cloudObservation(ndtom::testing::balmScan(2));
  b->timestamp = a->timestamp;

  const auto first = map.scanNdt(*a);
  ASSERT_TRUE(first);
  for (int i = 0; i < 5; ++i) map.computeObservationLikelihood(*a, poses[1]);
  EXPECT_EQ(map.scanNdt(*a), first) << "kept across particles";
  EXPECT_NE(map.scanNdt(*b), first) << "another object, even with the same time stamp";
  EXPECT_EQ(map.scanNdt(*a), first) << "a few observations are kept";
  a->timestamp += std::chrono::milliseconds(100);
  EXPECT_NE(map.scanNdt(*a), first) << "a new time stamp is a new observation";
  const auto refreshed = map.scanNdt(*a);
  a->sensorPose = CPose3D(0, 0, 0.5, 0, 0, 0);
  EXPECT_NE(map.scanNdt(*a), refreshed) << "the sensor moved on the robot";
  const auto moved = map.scanNdt(*a);
  map.likelihoodOptions.ndt_mcl_max_gaussians = 100;
  EXPECT_EQ(map.scanNdt(*a)->gaussians.size(), 100u) << "options are part of the key";
  EXPECT_EQ(moved->gaussians.size(), 300u);
  CNDTOccupancyMap copy(map);
  EXPECT_NE(copy.scanNdt(*a), map.scanNdt(*a)) << "a copy has its own cache";
}

TEST(LikelihoodNdtMcl, BadInputGivesFiniteValuesNeverAThrow) {
  const std::vector<CPose3D> poses = ndtom::testing::balmPoses();
  CNDTOccupancyMap map = ndtMclMap();
  for (int i = 0; i < 4; ++i)
    map.insertObservation(*cloudObservation(ndtom::testing::balmScan(i)), poses[size_t(i)]);
  const auto obs = cloudObservation(ndtom::testing::balmScan(5));
  const double at_pose = map.computeObservationLikelihood(*obs, poses[5]);
  const size_t kept = map.scanNdt(*obs)->gaussians.size();

  // No overlap: 1 km away, or a pose that is not finite: every scan Gaussian at the floor.
  const double floor = double(kept) * std::log(map.likelihoodOptions.outlier_likelihood);
  for (const CPose3D& pose : {poses[5] + CPose3D(1000, 0, 0, 0, 0, 0), CPose3D(NAN, 0, 0, 0, 0, 0),
                              CPose3D(1e300, 2, 0, 0, 0, 0)}) {
    const double value = map.computeObservationLikelihood(*obs, pose);
    EXPECT_TRUE(std::isfinite(value)) << pose.asString();
    EXPECT_NEAR(value, floor, 1e-9 * std::abs(floor)) << pose.asString();
    EXPECT_LT(value, at_pose - 100);
  }

  // No information: an empty cloud, a cloud of NaN points, a cloud too sparse for any
  // Gaussian, and an observation the map cannot read all score 0 at every pose, so the
  // particle weights stay as they were.
  auto nan_points = mrpt::maps::CSimplePointsMap::Create();
  for (int i = 0; i < 100; ++i) nan_points->insertPoint(NAN, 0, 0);
  auto sparse = mrpt::maps::CSimplePointsMap::Create();
  sparse->insertPoint(3, 0, 0);
  sparse->insertPoint(0, 7, 0);
  const mrpt::obs::CObservationOdometry odometry;
  EXPECT_FALSE(map.canComputeObservationLikelihood(odometry));
  for (const auto& points : {mrpt::maps::CSimplePointsMap::Create(), nan_points, sparse}) {
    const auto empty = cloudObservation(points);
    for (const CPose3D& pose :
         {poses[5], CPose3D(1000, 0, 0, 0, 0, 0), CPose3D(NAN, 0, 0, 0, 0, 0)}) {
      EXPECT_EQ(map.computeObservationLikelihood(*empty, pose), 0.0);
      EXPECT_EQ(map.computeObservationLikelihood(odometry, pose), 0.0);
    }
  }
  // An empty map: every Gaussian at the floor, wherever the particle is.
  CNDTOccupancyMap empty_map = ndtMclMap();
  EXPECT_NEAR(empty_map.computeObservationLikelihood(*obs, poses[5]), floor,
              1e-9 * std::abs(floor));
}

TEST(LikelihoodNdtMcl, OptionsSetInCodeAreCheckedWhenScoring) {
  // The .ini loader checks the options; set in code they are checked at the first score of
  // an observation, and a bad one throws naming it instead of scoring something else.
  const std::vector<CPose3D> poses = ndtom::testing::balmPoses();
  CNDTOccupancyMap map = ndtMclMap();
  map.insertObservation(*cloudObservation(ndtom::testing::balmScan(0)), poses[0]);
  const auto obs = cloudObservation(ndtom::testing::balmScan(1));
  const auto message = [&](auto change) {
    CNDTOccupancyMap copy(map);
    change(copy.likelihoodOptions);
    try {
      copy.computeObservationLikelihood(*obs, poses[1]);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  using O = CNDTOccupancyMap::TLikelihoodOptions;
  EXPECT_NE(message([](O& o) { o.ndt_mcl_max_gaussians = -5; }).find("ndt_mcl_max_gaussians = -5"),
            std::string::npos);
  EXPECT_NE(message([](O& o) { o.ndt_mcl_scan_factor = 0; }).find("ndt_mcl_scan_factor = 0"),
            std::string::npos);
  EXPECT_NE(message([](O& o) { o.ndt_mcl_map_factor = 0; }).find("ndt_mcl_map_factor"),
            std::string::npos);
  EXPECT_EQ(message([](O&) {}), "");
}

TEST(LikelihoodNdtMcl, ConcurrentCallsAgreeWithSequentialOnes) {
  // pf-localization runs its repetitions on several threads, each with its own observations,
  // over one map; the first calls also build the map table and the scan NDTs concurrently.
  const std::vector<CPose3D> poses = ndtom::testing::balmPoses();
  CNDTOccupancyMap map = ndtMclMap();
  for (int i = 0; i < 4; ++i)
    map.insertObservation(*cloudObservation(ndtom::testing::balmScan(i)), poses[size_t(i)]);
  std::vector<mrpt::obs::CObservationPointCloud::Ptr> observations;
  for (int i = 4; i < 10; ++i)
    observations.push_back(cloudObservation(ndtom::testing::balmScan(i)));
  const auto moves = offsets(0.2, 3 * kDeg);

  CNDTOccupancyMap sequential_map(map);
  std::vector<std::vector<double>> sequential(observations.size());
  for (size_t o = 0; o < observations.size(); ++o)
    for (const CPose3D& m : moves)
      sequential[o].push_back(
          sequential_map.computeObservationLikelihood(*observations[o], poses[o + 4] + m));

  std::vector<std::vector<double>> parallel(observations.size());
  std::vector<std::thread> threads;
  for (size_t o = 0; o < observations.size(); ++o)
    threads.emplace_back([&, o] {
      for (const CPose3D& m : moves)
        parallel[o].push_back(map.computeObservationLikelihood(*observations[o], poses[o + 4] + m));
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(parallel, sequential);
}
