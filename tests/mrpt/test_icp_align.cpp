// MRPT's own ICP (CICP::Align3D) with the NDT-OM as the reference map, on real lidar scans
// (BALM real-world, shipped subset): a map of scans inserted at their poses; a scan that is
// not in the map, started 0.3 m and 3° off its pose, must come back to within 3 cm and 0.3°.
#include <gtest/gtest.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/slam/CICP.h>

#include <Eigen/Geometry>
#include <iostream>

#include "balm_scans.h"
#include "mrpt_ndtom/CNDTOccupancyMap.h"

using mrpt::poses::CPose3D;
using mrpt_ndtom::CNDTOccupancyMap;
using ndtom::testing::balmScan;

namespace {

struct Fixture {
  std::vector<CPose3D> poses;
  CNDTOccupancyMap map{0.2};
};

// The map of every scan but `left_out`, inserted as MRPT point-cloud observations.
void buildMap(Fixture& f, int left_out) {
  f.poses = ndtom::testing::balmPoses();
  ASSERT_EQ(f.poses.size(), 10u);
  f.map.insertionOptions.scan.max_range = 30.0;
  for (int i = 0; i < 10; ++i) {
    if (i == left_out) continue;
    mrpt::obs::CObservationPointCloud obs;
    obs.pointcloud = balmScan(i);
    ASSERT_TRUE(f.map.insertObservation(obs, f.poses[i]));
  }
}

mrpt::slam::CICP icpForNdt() {
  mrpt::slam::CICP icp;
  icp.options.thresholdDist = 1.5;  // the 3° start moves points 20 m away by 1 m
  icp.options.thresholdAng = 0;
  icp.options.ALFA = 0.5;
  icp.options.smallestThresholdDist = 0.1;
  icp.options.maxIterations = 100;
  icp.options.corresponding_points_decimation = 4;
  return icp;
}

}  // namespace

TEST(IcpAlign, RecoversAKnownPerturbationOfARealScan) {
  Fixture f;
  const int k = 5;
  buildMap(f, k);
  const auto scan = balmScan(k);
  ASSERT_GT(scan->size(), 20000u);

  const double deg = M_PI / 180;
  // 0.3 m and 3°, spread over all axes.
  const std::vector<CPose3D> perturbations = {
      CPose3D(0.3, 0, 0, 3 * deg, 0, 0),
      CPose3D(0, -0.3, 0, 0, 3 * deg, 0),
      CPose3D(0, 0, 0.3, 0, 0, -3 * deg),
      CPose3D(0.3 / std::sqrt(3), 0.3 / std::sqrt(3), -0.3 / std::sqrt(3), -3 * deg / std::sqrt(3),
              3 * deg / std::sqrt(3), 3 * deg / std::sqrt(3)),
  };
  auto icp = icpForNdt();
  for (const auto& delta : perturbations) {
    const CPose3D start = f.poses[k] + delta;
    mrpt::slam::CICP::TReturnInfo info;
    const auto result = icp.Align3D(&f.map, scan.get(), start, info);
    ASSERT_TRUE(result);
    const CPose3D error = result->getMeanVal() - f.poses[k];
    const Eigen::Matrix3d rotation = error.getRotationMatrix().asEigen();
    const double angle = Eigen::AngleAxisd(rotation).angle();
    EXPECT_LT(error.translation().norm(), 0.03) << "start " << delta.asString();
    EXPECT_LT(angle / deg, 0.3) << "start " << delta.asString();
    EXPECT_GT(info.goodness, 0.5);
    std::cout << "[ icp      ] start " << delta.asString() << ": error "
              << 100 * error.translation().norm() << " cm, " << angle / deg << " deg, "
              << info.nIterations << " iterations\n";
  }
}

TEST(IcpAlign, MatchingPairsPointToTheSurface) {
  Fixture f;
  buildMap(f, -1);
  const auto scan = balmScan(3);
  mrpt::tfest::TMatchingPairList pairs;
  mrpt::maps::TMatchingParams params;
  params.maxDistForCorrespondence = 0.5;
  mrpt::maps::TMatchingExtraResults extra;
  f.map.determineMatching3D(scan.get(), f.poses[3], pairs, params, extra);
  ASSERT_GT(pairs.size(), scan->size() / 2);
  EXPECT_NEAR(extra.correspondencesRatio, double(pairs.size()) / scan->size(), 1e-6);
  // At the true pose a scan already in the map lies on its Gaussians' surfaces.
  std::vector<float> errors;
  for (const auto& p : pairs) {
    errors.push_back(p.errorSquareAfterTransformation);
    double gx, gy, gz;  // `local` is the scan point in its own frame
    f.poses[3].composePoint(p.local.x, p.local.y, p.local.z, gx, gy, gz);
    EXPECT_LT(std::hypot(gx - p.global.x, gy - p.global.y, gz - p.global.z), 0.5 + 1e-4);
  }
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  EXPECT_LT(std::sqrt(errors[errors.size() / 2]), 0.03) << "median point-to-surface distance";

  // Decimation and offset select points the way MRPT's points maps do.
  params.decimation_other_map_points = 10;
  params.offset_other_map_points = 3;
  f.map.determineMatching3D(scan.get(), f.poses[3], pairs, params, extra);
  for (const auto& p : pairs) EXPECT_EQ(p.localIdx % 10, 3u);

  // The ratio drops when the scan is moved away.
  mrpt::maps::TMatchingRatioParams ratio;
  const float at_truth = f.map.compute3DMatchingRatio(scan.get(), f.poses[3], ratio);
  const float moved =
      f.map.compute3DMatchingRatio(scan.get(), f.poses[3] + CPose3D(1, 0, 0, 0, 0, 0), ratio);
  EXPECT_GT(at_truth, 0.5f);
  EXPECT_LT(moved, 0.5f * at_truth);
}
