// CNDTOnlineMapper: the online mapper through MRPT's observations. On the shipped BALM scans,
// moved by known motions, it gives the poses the core's OnlineMapper gives for the same
// points (the second method), close to the known answer, with a covariance; the map it hands
// out is the core's.
#include <gtest/gtest.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationPointCloud.h>

#include <cmath>
#include <fstream>

#include "balm_scans.h"
#include "mrpt_ndtom/CNDTOnlineMapper.h"

using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace {

constexpr int kScans = 6;

struct MovedScans {
  std::vector<mrpt::obs::CObservationPointCloud::Ptr> observations;
  std::vector<std::vector<Vector3d>> points;  // as the observations hold them (float)
  std::vector<Isometry3d> truth;              // in the frame of scan 0
};

// Scan i as if the sensor had been at P_i·M_i (M_i: 0.8 m and 8° a scan): points M_i⁻¹·p.
MovedScans movedScans() {
  MovedScans out;
  const auto poses = ndtom::testing::balmPoses();
  std::ifstream times_file(ndtom::testing::kBalm + "/times.txt");
  Isometry3d motion = Isometry3d::Identity();
  for (int i = 0; i < kScans; ++i) {
    double t = 0;
    times_file >> t;
    if (i > 0) {
      motion.translate(Vector3d(0.8, 0.0, 0.0));
      motion.rotate(Eigen::AngleAxisd(8 * M_PI / 180, Vector3d::UnitZ()));
    }
    out.truth.push_back(ndtom::testing::toIsometry(poses[0]).inverse() *
                        ndtom::testing::toIsometry(poses[size_t(i)]) * motion);
    const auto scan = ndtom::testing::balmScan(i);
    auto moved = mrpt::maps::CSimplePointsMap::Create();
    std::vector<Vector3d> points;
    for (size_t k = 0; k < scan->size(); ++k) {
      float x, y, z;
      scan->getPoint(k, x, y, z);
      const Vector3d p = motion.inverse() * Vector3d(x, y, z);
      moved->insertPoint(float(p.x()), float(p.y()), float(p.z()));
      moved->getPoint(moved->size() - 1, x, y, z);
      points.emplace_back(x, y, z);
    }
    auto obs = mrpt::obs::CObservationPointCloud::Create();
    obs->pointcloud = moved;
    obs->timestamp = mrpt::Clock::fromDouble(t);
    out.observations.push_back(obs);
    out.points.push_back(points);
  }
  return out;
}

mrpt_ndtom::CNDTOccupancyMap::TInsertionOptions mapOptions() {
  mrpt_ndtom::CNDTOccupancyMap::TInsertionOptions o;
  o.resolution = 0.2;
  o.scan.max_range = 30;
  return o;
}

}  // namespace

TEST(CNDTOnlineMapper, GivesTheCoresPosesForTheSamePointsCloseToTheAnswer) {
  const MovedScans scans = movedScans();
  mrpt_ndtom::CNDTOnlineMapper mapper(mapOptions());
  ndtom::OnlineMapperOptions core_options;
  core_options.map = mapOptions().toMapOptions();
  ndtom::OnlineMapper core(core_options);
  for (int i = 0; i < kScans; ++i) {
    const mrpt::poses::CPose3DPDFGaussian pose = mapper.processObservation(*scans.observations[size_t(i)]);
    const ndtom::OnlineStep expected = core.process(
        scans.points[size_t(i)], Vector3d::Zero(),
        mrpt::Clock::toDouble(scans.observations[size_t(i)]->timestamp));
    EXPECT_NE(mapper.lastStep().outcome, ndtom::OnlineOutcome::Lost) << i;
    EXPECT_TRUE(mapper.lastStep().pose.matrix() == expected.pose.matrix()) << i;
    const Isometry3d got = ndtom::testing::toIsometry(pose.mean);
    EXPECT_LT((got.translation() - scans.truth[size_t(i)].translation()).norm(), 0.05) << i;
    if (i > 0) {
      for (int d = 0; d < 6; ++d) EXPECT_GT(pose.cov(d, d), 0) << i;
      EXPECT_LT(pose.cov(0, 0), 0.01) << i;
    }
  }
  const auto map = mapper.map();
  EXPECT_EQ(map->ndtMap().numCells(), core.map().numCells());
  EXPECT_EQ(map->ndtMap().numGaussians(), core.map().numGaussians());
  EXPECT_FALSE(map->isEmpty());
}

TEST(CNDTOnlineMapper, RefusesWhatItCannotMap) {
  mrpt_ndtom::CNDTOnlineMapper mapper(mapOptions());
  mrpt::obs::CObservationOdometry odometry;
  EXPECT_THROW(mapper.processObservation(odometry), std::invalid_argument);
  EXPECT_TRUE(mapper.ndtMap().isEmpty());
  auto bad = mapOptions();
  bad.resolution = -1;
  EXPECT_THROW(mrpt_ndtom::CNDTOnlineMapper{bad}, std::invalid_argument);
}
