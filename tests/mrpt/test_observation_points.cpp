// The observation adapter on small synthetic observations of every supported type, checked
// against MRPT's own geometry (CPose3D::composePoint, unprojectInto), and the map's handling
// of unsupported and empty observations.
#include <gtest/gtest.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationPointCloud.h>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom/files/map_io.h"

using Eigen::Vector3d;
using mrpt::poses::CPose3D;
using mrpt_ndtom::observationPoints;

namespace {

const CPose3D kRobot(1.5, -2.0, 0.3, 0.4, 0.05, -0.02);  // x y z yaw pitch roll
const CPose3D kSensor(0.2, 0.1, 0.6, -0.3, 0.1, 0.02);   // on the robot

Vector3d mrptWorld(const CPose3D& sensor, double x, double y, double z) {
  double gx, gy, gz;
  (kRobot + sensor).composePoint(x, y, z, gx, gy, gz);
  return {gx, gy, gz};
}

mrpt::obs::CObservation2DRangeScan scan2D() {
  mrpt::obs::CObservation2DRangeScan scan;
  scan.aperture = float(M_PI);
  scan.rightToLeft = true;
  scan.resizeScan(5);
  const float ranges[5] = {1.0f, 2.5f, 3.0f, 0.0f, 4.25f};
  for (size_t i = 0; i < 5; ++i) {
    scan.setScanRange(i, ranges[i]);
    scan.setScanRangeValidity(i, i != 3);
  }
  scan.sensorPose = kSensor;
  return scan;
}

mrpt::obs::CObservation3DRangeScan depthScan(bool range_is_depth) {
  mrpt::obs::CObservation3DRangeScan o;
  o.hasRangeImage = true;
  o.range_is_depth = range_is_depth;
  o.rangeUnits = 0.001f;
  o.rangeImage.resize(6, 8);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 8; ++c)
      o.rangeImage(r, c) = uint16_t((r * 8 + c) % 5 ? 1000 + 37 * r + 11 * c : 0);
  o.cameraParams.ncols = 8;
  o.cameraParams.nrows = 6;
  o.cameraParams.fx(7.5);
  o.cameraParams.fy(7.0);
  o.cameraParams.cx(3.7);
  o.cameraParams.cy(2.4);
  o.sensorPose = kSensor;
  return o;
}

void expectSamePoints(const std::vector<Vector3d>& got, const std::vector<Vector3d>& want,
                      double tol) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < got.size(); ++i)
    EXPECT_LE((got[i] - want[i]).norm(), tol) << "point " << i;
}

}  // namespace

TEST(ObservationPoints, Scan2D) {
  const auto scan = scan2D();
  const auto got = observationPoints(scan, kRobot);
  ASSERT_TRUE(got);
  std::vector<Vector3d> want;
  for (size_t i = 0; i < 5; ++i) {
    if (i == 3) continue;  // invalid reading
    const double r = scan.getScanRange(i), a = -M_PI / 2 + i * M_PI / 4;
    want.push_back(mrptWorld(kSensor, r * std::cos(a), r * std::sin(a), 0));
  }
  expectSamePoints(got->points_world, want, 1e-6);
  EXPECT_LT((got->sensor_origin - mrptWorld(kSensor, 0, 0, 0)).norm(), 1e-12);

  const auto decimated = observationPoints(scan, kRobot, {2, 1});  // readings 0, 2, 4
  ASSERT_TRUE(decimated);
  expectSamePoints(decimated->points_world, {want[0], want[2], want[3]}, 1e-6);
  EXPECT_THROW(observationPoints(scan, kRobot, {0, 1}), std::invalid_argument);
}

TEST(ObservationPoints, DepthImageMatchesMrptsUnprojection) {
  for (const bool range_is_depth : {true, false}) {
    auto obs = depthScan(range_is_depth);
    const auto got = observationPoints(obs, kRobot);
    ASSERT_TRUE(got);
    mrpt::maps::CSimplePointsMap mrpt_points;
    mrpt::obs::T3DPointsProjectionParams pp;
    pp.takeIntoAccountSensorPoseOnRobot = true;
    pp.robotPoseInTheWorld = kRobot;
    obs.unprojectInto(mrpt_points, pp);
    std::vector<Vector3d> want;
    for (size_t i = 0; i < mrpt_points.size(); ++i) {
      double x, y, z;
      mrpt_points.getPoint(i, x, y, z);
      want.push_back({x, y, z});
    }
    ASSERT_EQ(want.size(), 6u * 8u - 10u) << "zero pixels are not points";
    expectSamePoints(got->points_world, want, 1e-5);  // MRPT's LUT is float
    EXPECT_LT((got->sensor_origin - mrptWorld(kSensor, 0, 0, 0)).norm(), 1e-12);
  }
}

TEST(ObservationPoints, DepthImageDecimationTakesEveryNthRowAndColumn) {
  const auto obs = depthScan(true);
  const auto all = observationPoints(obs, kRobot);
  const auto every2 = observationPoints(obs, kRobot, {1, 2});
  ASSERT_TRUE(all && every2);
  std::vector<Vector3d> want;
  size_t k = 0;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 8; ++c) {
      if (obs.rangeImage(r, c) == 0) continue;
      if (r % 2 == 0 && c % 2 == 0) want.push_back(all->points_world[k]);
      ++k;
    }
  expectSamePoints(every2->points_world, want, 0.0);
}

TEST(ObservationPoints, StoredPoints3D) {
  mrpt::obs::CObservation3DRangeScan obs;
  obs.hasPoints3D = true;
  obs.points3D_x = {1.0f, 0.0f, 2.0f};
  obs.points3D_y = {0.5f, 0.0f, -1.0f};
  obs.points3D_z = {0.2f, 0.0f, 0.3f};  // the middle one is (0,0,0): no reading
  obs.sensorPose = kSensor;
  const auto got = observationPoints(obs, kRobot);
  ASSERT_TRUE(got);
  expectSamePoints(got->points_world,
                   {mrptWorld(kSensor, 1.0, 0.5, 0.2), mrptWorld(kSensor, 2.0, -1.0, 0.3)}, 1e-6);
}

TEST(ObservationPoints, PointCloudUsesRobotAndSensorPose) {
  mrpt::obs::CObservationPointCloud obs;
  auto cloud = mrpt::maps::CSimplePointsMap::Create();
  cloud->insertPoint(3.0f, 1.0f, 0.5f);
  cloud->insertPoint(-1.0f, 2.0f, 1.5f);
  obs.pointcloud = cloud;
  obs.sensorPose = kSensor;
  const auto got = observationPoints(obs, kRobot);
  ASSERT_TRUE(got);
  expectSamePoints(got->points_world,
                   {mrptWorld(kSensor, 3, 1, 0.5), mrptWorld(kSensor, -1, 2, 1.5)}, 1e-6);
  mrpt::obs::CObservationPointCloud no_cloud;  // null pointcloud: no points, not an error
  const auto none = observationPoints(no_cloud, kRobot);
  ASSERT_TRUE(none);
  EXPECT_TRUE(none->points_world.empty());
}

TEST(ObservationPoints, UnsupportedTypes) {
  mrpt::obs::CObservationOdometry odometry;
  EXPECT_FALSE(mrpt_ndtom::isSupportedObservation(odometry));
  EXPECT_FALSE(observationPoints(odometry, kRobot).has_value());
  EXPECT_TRUE(mrpt_ndtom::isSupportedObservation(scan2D()));
}

TEST(ObservationPoints, MapIgnoresUnsupportedAndEmptyObservations) {
  mrpt_ndtom::CNDTOccupancyMap map(0.25);
  ASSERT_TRUE(map.insertObservation(scan2D(), kRobot));
  const auto before = ndtom::encodeMap(map.ndtMap());

  mrpt::obs::CObservationOdometry odometry;
  EXPECT_FALSE(map.insertObservation(odometry, kRobot));
  EXPECT_FALSE(map.canComputeObservationLikelihood(odometry));

  auto invalid = scan2D();  // every reading invalid
  for (size_t i = 0; i < invalid.getScanSize(); ++i) invalid.setScanRangeValidity(i, false);
  EXPECT_FALSE(map.insertObservation(invalid, kRobot));

  mrpt::obs::CObservation3DRangeScan nothing;  // neither image nor points
  EXPECT_FALSE(map.insertObservation(nothing, kRobot));

  EXPECT_EQ(ndtom::encodeMap(map.ndtMap()), before);
}

TEST(ObservationPoints, InsertionUsesSensorOriginOnTheRobot) {
  // The free ray of a single reading starts at robot ⊕ sensor, not at the robot.
  mrpt_ndtom::CNDTOccupancyMap map(0.1);
  mrpt::obs::CObservation2DRangeScan scan;
  scan.aperture = 0.2f;
  scan.resizeScan(3);  // only the middle reading (straight ahead) is valid
  for (size_t i = 0; i < 3; ++i) {
    scan.setScanRange(i, 3.0f);
    scan.setScanRangeValidity(i, i == 1);
  }
  scan.sensorPose = CPose3D(0, 0, 1.0, 0, 0, 0);
  ASSERT_TRUE(map.insertObservation(scan, CPose3D(5, 5, 0, 0, 0, 0)));
  EXPECT_TRUE(map.ndtMap().cellAt(Vector3d(6.5, 5.0, 1.0)).has_value()) << "on the ray";
  EXPECT_FALSE(map.ndtMap().cellAt(Vector3d(6.5, 5.0, 0.0)).has_value()) << "robot height";
  EXPECT_FALSE(map.ndtMap().cellAt(Vector3d(4.5, 5.0, 1.0)).has_value()) << "behind";
}
