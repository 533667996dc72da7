// CNDTRegistration through MRPT's alignment interface: a real lidar scan (the shipped BALM
// subset) and a real 2D laser scan (MRPT's Malaga simplemap) moved off their poses come back
// to them; options round-trip through .ini text; the covariance conversion to MRPT's
// (yaw, pitch, roll) agrees with finite differences of CPose3D itself.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/slam/CICP.h>

#include "balm_scans.h"
#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "mrpt_ndtom/CNDTRegistration.h"
#include "support/thrown_message.h"

using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;
using mrpt_ndtom::CNDTOccupancyMap;
using mrpt_ndtom::CNDTRegistration;
using ndtom::testing::thrownMessage;

namespace {

const double kDeg = M_PI / 180;
const std::string kDatasets = MRPT_DATASETS;

double rotationErrorDeg(const CPose3D& a, const CPose3D& b) {
  const CPose3D d = a - b;
  return Eigen::AngleAxisd(d.getRotationMatrix().asEigen()).angle() / kDeg;
}

}  // namespace

TEST(NdtRegistrationMrpt, AlignsARealLidarScanThroughTheBaseClass) {
  const auto poses = ndtom::testing::balmPoses();
  const int k = 5;
  CNDTOccupancyMap map(0.2);
  map.insertionOptions.scan.max_range = 30;
  for (int i = 0; i < 10; ++i) {
    if (i == k) continue;
    mrpt::obs::CObservationPointCloud obs;
    obs.pointcloud = ndtom::testing::balmScan(i);
    ASSERT_TRUE(map.insertObservation(obs, poses[i]));
  }
  const auto scan = ndtom::testing::balmScan(k);
  const CPose3D guess = poses[k] + CPose3D(1.0, -0.6, 0.1, 10 * kDeg, 0, 0);

  CNDTRegistration ndt;
  mrpt::slam::CMetricMapsAlignmentAlgorithm& aligner = ndt;  // where users had CICP
  CNDTRegistration::TReturnInfo info;
  const auto pdf = aligner.Align3D(&map, scan.get(), guess, info);
  ASSERT_TRUE(pdf);
  const auto gaussian = std::dynamic_pointer_cast<mrpt::poses::CPose3DPDFGaussian>(pdf);
  ASSERT_TRUE(gaussian);
  EXPECT_TRUE(info.result.converged) << info.result.failure;
  EXPECT_LT((gaussian->mean.translation() - poses[k].translation()).norm(), 0.02);
  EXPECT_LT(rotationErrorDeg(gaussian->mean, poses[k]), 0.2);
  EXPECT_GT(info.executionTime, 0);
  EXPECT_EQ(info.result.levels.size(), 5u);
  for (int d = 0; d < 6; ++d) EXPECT_GT(gaussian->cov(d, d), 0);
  EXPECT_LT(gaussian->cov(0, 0), 1e-2);

  // The second call reuses the pyramid; a scan far from the map is reported as failed.
  const auto far = aligner.Align3D(&map, scan.get(), poses[k] + CPose3D(500, 0, 0, 0, 0, 0), info);
  EXPECT_FALSE(info.result.pyramid_rebuilt);
  EXPECT_FALSE(info.result.converged);
  EXPECT_FALSE(info.result.failure.empty());

  // The wrong map types are refused with a message.
  mrpt::maps::CSimplePointsMap points;
  EXPECT_NE(
      thrownMessage([&] { aligner.Align3D(&points, scan.get(), guess); }).find("CNDTOccupancyMap"),
      std::string::npos);
  EXPECT_NE(thrownMessage([&] { aligner.Align3D(&map, &map, guess); }).find("CPointsMap"),
            std::string::npos);
  mrpt::maps::CSimplePointsMap empty;
  EXPECT_NE(thrownMessage([&] { aligner.Align3D(&map, &empty, guess); }).find("no finite point"),
            std::string::npos);
}

TEST(NdtRegistrationMrpt, AlignsARealLaserScanIn2D) {
  mrpt::maps::CSimpleMap simplemap;
  ASSERT_TRUE(simplemap.loadFromFile(kDatasets + "/malaga-cs-fac-building.simplemap.gz"))
      << "needs Debian's mrpt-common";
  const size_t k = 20;  // left out of the map
  CNDTOccupancyMap map(0.2);
  CPose3D truth;
  mrpt::maps::CSimplePointsMap scan;
  for (size_t i = 0; i < 40; ++i) {
    const auto& [pose_pdf, frame] = simplemap.get(i);
    const CPose3D robot = pose_pdf->getMeanVal();
    for (const auto& obs : *frame) {
      const auto laser = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs);
      if (!laser) continue;
      if (i == k) {
        truth = robot;
        scan.loadFromRangeScan(*laser);  // in the robot frame
      } else {
        ASSERT_TRUE(map.insertObservation(*laser, robot));
      }
    }
  }
  ASSERT_GT(scan.size(), 100u);
  const CPose2D truth2d(truth);
  const CPose2D guess(truth2d.x() + 0.4, truth2d.y() - 0.3, truth2d.phi() + 6 * kDeg);

  CNDTRegistration ndt;
  mrpt::slam::CMetricMapsAlignmentAlgorithm& aligner = ndt;
  CNDTRegistration::TReturnInfo info;
  const auto pdf = aligner.Align(&map, &scan, guess, info);
  const auto gaussian = std::dynamic_pointer_cast<mrpt::poses::CPosePDFGaussian>(pdf);
  ASSERT_TRUE(gaussian);
  EXPECT_TRUE(info.result.converged) << info.result.failure;
  EXPECT_LT(std::hypot(gaussian->mean.x() - truth2d.x(), gaussian->mean.y() - truth2d.y()), 0.05);
  EXPECT_LT(std::abs(mrpt::math::wrapToPi(gaussian->mean.phi() - truth2d.phi())) / kDeg, 0.5);
  for (int d = 0; d < 3; ++d) EXPECT_GT(gaussian->cov(d, d), 0);
}

TEST(NdtRegistrationMrpt, OptionsRoundTripThroughIniText) {
  CNDTRegistration::TConfigParams o;
  o.core.method = ndtom::RegistrationMethod::D2D;
  o.core.level_factors = {8, 2, 1};
  o.core.outlier_ratio = 0.3;
  o.core.max_iterations = 12;
  o.core.max_points = 1234;
  o.core.max_range = 40;
  o.core.planar = true;
  o.core.max_free_fraction = 0.2;
  o.core.threads = 2;
  mrpt::config::CConfigFileMemory ini;
  o.saveToConfigFile(ini, "NDT");
  CNDTRegistration::TConfigParams back;  // through the text, as a saved file is read
  back.loadFromConfigFile(mrpt::config::CConfigFileMemory(ini.getContent()), "NDT");
  EXPECT_EQ(back.core.method, o.core.method);
  EXPECT_EQ(back.core.level_factors, o.core.level_factors);
  EXPECT_EQ(back.core.outlier_ratio, o.core.outlier_ratio);
  EXPECT_EQ(back.core.max_iterations, o.core.max_iterations);
  EXPECT_EQ(back.core.max_points, o.core.max_points);
  EXPECT_EQ(back.core.max_range, o.core.max_range);
  EXPECT_EQ(back.core.planar, o.core.planar);
  EXPECT_EQ(back.core.max_free_fraction, o.core.max_free_fraction);
  EXPECT_EQ(back.core.threads, o.core.threads);

  const std::vector<std::pair<std::string, std::string>> bad = {
      {"method = icp", "method"},
      {"level_factors = 1 2", "level_factors"},
      {"level_factors = 4 x", "level_factors"},
      {"outlier_ratio = 1", "outlier_ratio"},
      {"max_iterations = 1e3", "max_iterations"},
      {"threads = 0", "threads"},
      {"max_points = 3", "max_points"},
      {"min_matched_fraction = 2", "min_matched_fraction"},
      {"max_free_fraction = -1", "max_free_fraction"},
      // #38: MRPT's readers took these as false, 0.2, 2, 3 and 1 without a word.
      {"planar = maybe", "planar: expected true or false, got 'maybe'"},
      {"outlier_ratio = 0.2abc", "outlier_ratio: not a number: '0.2abc'"},
      {"max_iterations = 4294967298", "max_iterations = 4294967298: must be in [1, 1000]"},
      {"threads = 3x", "threads: not an integer: '3x'"},
      {"level_factors = 8 4x 1", "level_factors: not an integer: '4x'"},
      {"translation_epsilon =", "translation_epsilon: not a number: ''"},
      {"max_range = 40 m", "max_range: not a number: '40 m'"},
      {"rotation_epsilon = inf", "rotation_epsilon: must be finite, got 'inf'"},
  };
  for (const auto& [body, option] : bad) {
    CNDTRegistration::TConfigParams p;
    const std::string msg = thrownMessage(
        [&] { p.loadFromConfigFile(mrpt::config::CConfigFileMemory("[s]\n" + body), "s"); });
    EXPECT_NE(msg.find("[s] " + option), std::string::npos) << body << " -> " << msg;
  }
  // A comment after the value, an infinite range and a bool in capitals still load.
  CNDTRegistration::TConfigParams p;
  p.loadFromConfigFile(mrpt::config::CConfigFileMemory("[s]\nmax_range = inf # none\n"
                                                       "level_factors = 4 1 ; coarse, fine\n"
                                                       "planar = TRUE\nmethod = d2d # scan NDT\n"),
                       "s");
  EXPECT_EQ(p.core.max_range, INFINITY);
  EXPECT_EQ(p.core.level_factors, (std::vector<int>{4, 1}));
  EXPECT_TRUE(p.core.planar);
  EXPECT_EQ(p.core.method, ndtom::RegistrationMethod::D2D);
}

TEST(NdtRegistrationMrpt, CovarianceInMrptsAnglesMatchesFiniteDifferences) {
  const CPose3D pose(1, 2, 3, 40 * kDeg, -25 * kDeg, 70 * kDeg);
  // The oracle: MRPT's own (x, y, z, yaw, pitch, roll) of pose ⊕ δ for small δ, δ = (v, ω).
  Eigen::Matrix<double, 6, 6> jacobian;
  const double h = 1e-6;
  auto paramsOf = [&](const Eigen::Matrix<double, 6, 1>& delta) {
    Eigen::Isometry3d t = mrpt_ndtom::toIsometry(pose);
    const Eigen::Vector3d w = delta.tail<3>();
    if (w.norm() > 0) t.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()) * t.linear();
    t.translation() += delta.head<3>();
    mrpt::math::CMatrixDouble44 m;
    m.asEigen() = t.matrix();
    const CPose3D p(m);
    Eigen::Matrix<double, 6, 1> out;
    out << p.x(), p.y(), p.z(), p.yaw(), p.pitch(), p.roll();
    return out;
  };
  for (int k = 0; k < 6; ++k) {
    Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
    d[k] = h;
    jacobian.col(k) = (paramsOf(d) - paramsOf(-d)) / (2 * h);
  }
  Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Random();
  const ndtom::Matrix6d covariance = a * a.transpose();
  const auto mrpt_cov = mrpt_ndtom::toMrptPoseCovariance(covariance, pose);
  const Eigen::Matrix<double, 6, 6> expected = jacobian * covariance * jacobian.transpose();
  EXPECT_TRUE(mrpt_cov.asEigen().isApprox(expected, 1e-6)) << mrpt_cov.asEigen() << "\n\n"
                                                           << expected;
}
