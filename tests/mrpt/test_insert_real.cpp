// Inserting the real observations that ship with MRPT (Debian's mrpt-common): the RGB-D
// frame, the VLP-16 scan and the Málaga 2D laser scans. The map must equal the core map
// built from the same points extracted by MRPT's own code (unprojectInto,
// generatePointCloud, CSimplePointsMap::loadFromRangeScan) and its sensor origin.
// And the project's BALM lidar scans: the map does not depend on the insertion threads.
#include <gtest/gtest.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDF.h>
#include <mrpt/serialization/CArchive.h>

#include "balm_scans.h"
#include "map_compare.h"
#include "mrpt_ndtom/CNDTOccupancyMap.h"

using Eigen::Vector3d;
using mrpt::poses::CPose3D;
using mrpt_ndtom::CNDTOccupancyMap;

namespace {

const std::string kDatasets = MRPT_DATASETS;

template <class T>
typename T::Ptr firstObservation(const std::string& file) {
  mrpt::obs::CRawlog rawlog;
  if (!rawlog.loadFromRawLogFile(kDatasets + "/" + file)) return nullptr;
  for (size_t i = 0; i < rawlog.size(); ++i)
    if (rawlog.getType(i) == mrpt::obs::CRawlog::etObservation)
      if (auto obs = std::dynamic_pointer_cast<T>(rawlog.getAsObservation(i))) return obs;
  return nullptr;
}

std::vector<Vector3d> toVectors(const mrpt::maps::CPointsMap& points) {
  std::vector<Vector3d> out(points.size());
  for (size_t i = 0; i < points.size(); ++i) points.getPoint(i, out[i].x(), out[i].y(), out[i].z());
  return out;
}

Vector3d originOf(const CPose3D& robot, const mrpt::obs::CObservation& obs) {
  CPose3D sensor;
  obs.getSensorPose(sensor);
  const CPose3D origin = robot + sensor;
  return {origin.x(), origin.y(), origin.z()};
}

ndtom::MapOptions optionsOf(const CNDTOccupancyMap& map) {
  return map.insertionOptions.toMapOptions();
}

std::vector<uint8_t> archiveBytes(const CNDTOccupancyMap& map) {
  mrpt::io::CMemoryStream buffer;
  mrpt::serialization::archiveFrom(buffer) << map;
  const auto* raw = static_cast<const uint8_t*>(buffer.getRawBufferData());
  return {raw, raw + buffer.getTotalBytesCount()};
}

}  // namespace

TEST(InsertReal, RgbdFrameMatchesMrptUnprojection) {
  auto obs = firstObservation<mrpt::obs::CObservation3DRangeScan>("tests_rgbd.rawlog");
  ASSERT_TRUE(obs) << "needs Debian's mrpt-common";
  ASSERT_TRUE(obs->hasRangeImage);
  const CPose3D robot(1.0, 2.0, 0.5, 0.5, 0.08, -0.05);

  CNDTOccupancyMap map(0.05);
  ASSERT_TRUE(map.insertObservation(*obs, robot));

  // Independent: MRPT's unprojection of every pixel, in the world frame.
  mrpt::maps::CSimplePointsMap points;
  mrpt::obs::T3DPointsProjectionParams pp;
  pp.takeIntoAccountSensorPoseOnRobot = true;
  pp.robotPoseInTheWorld = robot;
  obs->unprojectInto(points, pp);
  ASSERT_GT(points.size(), 100000u);
  ndtom::NdtMap expected(optionsOf(map));
  expected.insertScan(toVectors(points), originOf(robot, *obs));

  EXPECT_EQ(map.lastInsertionReport().points_in, points.size());
  ndtom::testing::expectNearlySameMaps(map.ndtMap(), expected);
  EXPECT_GT(map.ndtMap().numGaussians(), 1000u);
}

TEST(InsertReal, VelodyneScanMatchesMrptPointCloud) {
  auto obs = firstObservation<mrpt::obs::CObservationVelodyneScan>("test_velodyne_VLP16.rawlog");
  ASSERT_TRUE(obs) << "needs Debian's mrpt-common";
  const CPose3D robot(-3.0, 0.5, 1.2, -0.7, 0.02, 0.01);

  CNDTOccupancyMap map(0.2);
  ASSERT_TRUE(map.insertObservation(*obs, robot));
  EXPECT_EQ(obs->point_cloud.size(), 0u) << "the adapter leaves the observation as it was";

  // Independent: MRPT's own point cloud, moved by MRPT's pose composition.
  auto copy = *obs;
  copy.generatePointCloud();
  ASSERT_GT(copy.point_cloud.size(), 10000u);
  const CPose3D sensor_in_world = robot + copy.sensorPose;
  std::vector<Vector3d> points;
  for (size_t i = 0; i < copy.point_cloud.size(); ++i) {
    Vector3d p;
    sensor_in_world.composePoint(copy.point_cloud.x[i], copy.point_cloud.y[i],
                                 copy.point_cloud.z[i], p.x(), p.y(), p.z());
    points.push_back(p);
  }
  ndtom::NdtMap expected(optionsOf(map));
  expected.insertScan(points, originOf(robot, copy));
  ndtom::testing::expectNearlySameMaps(map.ndtMap(), expected, 1e-4);

  // A point cloud already stored in the observation is used as is.
  CNDTOccupancyMap from_stored(0.2);
  ASSERT_TRUE(from_stored.insertObservation(copy, robot));
  ndtom::testing::expectNearlySameMaps(from_stored.ndtMap(), expected, 1e-4);
}

TEST(InsertReal, MalagaLaserScansMatchMrptPointsMaps) {
  mrpt::maps::CSimpleMap simplemap;
  ASSERT_TRUE(simplemap.loadFromFile(kDatasets + "/malaga-cs-fac-building.simplemap.gz"))
      << "needs Debian's mrpt-common";
  ASSERT_GT(simplemap.size(), 30u);

  CNDTOccupancyMap map(0.1);
  ndtom::NdtMap expected(optionsOf(map));
  size_t scans = 0;
  for (size_t k = 0; k < 30; ++k) {
    const auto& [pose_pdf, frame] = simplemap.get(k);
    const CPose3D robot = pose_pdf->getMeanVal();
    for (const auto& obs : *frame) {
      const auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs);
      if (!scan) continue;
      ASSERT_TRUE(map.insertObservation(*scan, robot));
      mrpt::maps::CSimplePointsMap points;
      points.insertionOptions.minDistBetweenLaserPoints = 0;  // keep every reading
      points.loadFromRangeScan(*scan, robot);
      expected.insertScan(toVectors(points), originOf(robot, *scan));
      ++scans;
    }
  }
  ASSERT_GE(scans, 30u);
  // MRPT stores the end points as float. Rays of up to 30 m that pass within that rounding of
  // a cell corner visit a different neighbour: measured 145 of 130,675 cells (0.11%) with
  // other log-odds, 2 with another point count, none missing.
  ndtom::testing::expectNearlySameMaps(map.ndtMap(), expected, 2e-3);
  EXPECT_GT(map.ndtMap().numGaussians(), 500u);
  EXPECT_GT(map.ndtMap().numCells(), 10 * map.ndtMap().numGaussians()) << "free space traced";
}

TEST(InsertReal, WholeSimplemapThroughMrptsLoader) {
  // CMetricMap::loadFromSimpleMap (what observations2map calls) inserts every observation at
  // its frame's mean pose: the same map as inserting them one by one.
  mrpt::maps::CSimpleMap simplemap;
  ASSERT_TRUE(simplemap.loadFromFile(kDatasets + "/malaga-cs-fac-building.simplemap.gz"));
  CNDTOccupancyMap via_loader(0.2), by_hand(0.2);
  via_loader.loadFromSimpleMap(simplemap);
  for (const auto& [pose_pdf, frame] : simplemap)
    for (const auto& obs : *frame) by_hand.insertObservation(*obs, pose_pdf->getMeanVal());
  ndtom::testing::expectNearlySameMaps(via_loader.ndtMap(), by_hand.ndtMap(), 0.0);
}

TEST(InsertReal, TwoThreadsBuildTheSameMapAsOne) {
  // Six BALM lidar scans as point clouds, 0.2 m cells, rays up to 30 m, in both ray modes.
  const std::vector<CPose3D> poses = ndtom::testing::balmPoses();
  ASSERT_GE(poses.size(), 6u);
  std::vector<mrpt::obs::CObservationPointCloud> scans(6);
  for (size_t i = 0; i < scans.size(); ++i) scans[i].pointcloud = ndtom::testing::balmScan(int(i));
  for (const auto mode : {ndtom::RayMode::PerPoint, ndtom::RayMode::PerHitCell}) {
    CNDTOccupancyMap one(0.2), two(0.2);
    for (CNDTOccupancyMap* map : {&one, &two}) {
      map->insertionOptions.scan.max_range = 30.0;
      map->insertionOptions.scan.ray_mode = mode;
    }
    two.insertionOptions.scan.threads = 2;
    for (size_t i = 0; i < scans.size(); ++i) {
      ASSERT_TRUE(one.insertObservation(scans[i], poses[i]));
      ASSERT_TRUE(two.insertObservation(scans[i], poses[i]));
    }
    ASSERT_GT(one.ndtMap().numGaussians(), 5000u) << ndtom::toString(mode);
    EXPECT_GT(one.ndtMap().numCells(), 5 * one.ndtMap().numGaussians()) << "free space traced";
    // Every cell, bit for bit: the whole archive, once the option itself agrees.
    two.insertionOptions.scan.threads = 1;
    EXPECT_TRUE(archiveBytes(one) == archiveBytes(two)) << ndtom::toString(mode);
  }
}

// The memory budget through the plugin (issue #17): a 153-byte rawlog's one 2D scan at 6 km,
// with no range limit, took over 4 GB; with memory_budget = 64 (MB) it is refused with the
// option named, the map unchanged, and the default max_range (100 m) makes it harmless.
TEST(InsertReal, ScanOverTheMemoryBudgetIsRefusedAndTheMapKept) {
  mrpt::obs::CObservation2DRangeScan scan;
  scan.aperture = float(M_PI);
  scan.resizeScan(361);
  for (size_t i = 0; i < 361; ++i) {
    scan.setScanRange(i, 6000.f);
    scan.setScanRangeValidity(i, true);
  }
  scan.maxRange = 8000.f;
  CNDTOccupancyMap map(0.2);
  const auto scans = ndtom::testing::balmPoses();
  mrpt::obs::CObservationPointCloud near;
  near.pointcloud = ndtom::testing::balmScan(0);
  ASSERT_TRUE(map.insertObservation(near, scans[0]));
  // Every cell's bytes (the archive would also show the options the next insertion applies).
  auto cells = [](const CNDTOccupancyMap& m) {
    std::vector<uint8_t> bytes;
    m.ndtMap().forEachCellOrdered([&](const ndtom::CellView& c) {
      const auto* p = reinterpret_cast<const uint8_t*>(&c.index);
      bytes.insert(bytes.end(), p, p + sizeof(c.index));
      p = reinterpret_cast<const uint8_t*>(&c.logodds);
      bytes.insert(bytes.end(), p, p + sizeof(c.logodds));
      if (!c.stats) return;
      for (const double v :
           {c.stats->relative_mean.x(), c.stats->relative_mean.y(), c.stats->relative_mean.z(),
            double(c.stats->n), c.stats->scatter.sum()}) {
        p = reinterpret_cast<const uint8_t*>(&v);
        bytes.insert(bytes.end(), p, p + sizeof(v));
      }
    });
    return bytes;
  };
  const auto before = cells(map);
  map.insertionOptions.scan.max_range = std::numeric_limits<double>::infinity();
  map.insertionOptions.scan.memory_budget = 64000000;  // bytes
  try {
    map.insertObservation(scan, CPose3D());
    FAIL() << "accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("memory budget of 64"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("(memory_budget)"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(cells(map) == before) << "the refused scan changed the map";
  map.insertionOptions.scan.max_range = ndtom::kDefaultMaxRange;
  EXPECT_TRUE(map.insertObservation(scan, CPose3D()));  // truncated at 100 m: 500 cells a ray
  EXPECT_GT(map.lastInsertionReport().truncated, 300u);
}
