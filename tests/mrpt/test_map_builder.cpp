// CMetricMapBuilderNDT on MRPT's SENA log (224 real 2D laser scans with odometry), used
// through MRPT's base class as icp-slam uses its builder. Oracles: CNDTOnlineMapper driven
// by hand with the same scans and odometry (the poses and the map, bit for bit), MRPT's own
// CMetricMapBuilderICP and reference poses of the log, the log's odometry, and a map
// rebuilt from the builder's CSimpleMap by CNDTOccupancyMap's own insertion.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/img/CImage.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/slam/CMetricMapBuilderICP.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>

#include "balm_scans.h"
#include "mrpt_ndtom/CMetricMapBuilderNDT.h"
#include "ndtom/map/map_queries.h"
#include "sena_log.h"

namespace {

using mrpt::poses::CPose3D;
using mrpt_ndtom::CMetricMapBuilderNDT;
using ndtom::testing::ActionFrame;

const std::string kIni = std::string(NDTOM_SOURCE_DIR) + "/share/mrpt/ndtom-slam.ini";

CMetricMapBuilderNDT::TConfigParams shippedOptions() {
  CMetricMapBuilderNDT::TConfigParams o;
  o.loadFromConfigFile(mrpt::config::CConfigFile(kIni), "NDTSLAM");
  return o;
}

CPose3D odometryOf(const ActionFrame& p) {
  return CPose3D(p.actions->getBestMovementEstimation()->poseChange->getMeanVal());
}

CPose3D meanOf(const mrpt::slam::CMetricMapBuilder& builder) {
  return builder.getCurrentPoseEstimation()->getMeanVal();
}

double distance2d(const CPose3D& a, const CPose3D& b) {
  return std::hypot(a.x() - b.x(), a.y() - b.y());
}

struct Errors {
  double mean = 0, worst = 0;
  size_t compared = 0;
};

// Against MRPT's reference poses of the log, matched by time stamp.
Errors referenceErrors(const std::vector<CPose3D>& poses, const std::vector<ActionFrame>& log) {
  static const auto reference = ndtom::testing::senaReferencePoses();
  Errors e;
  for (size_t i = 0; i < log.size(); ++i) {
    const auto it = reference.find(
        std::lround(mrpt::Clock::toDouble((*log[i].frame->begin())->timestamp) * 1e3));
    if (it == reference.end()) continue;
    const double d = distance2d(poses[i], it->second);
    e.worst = std::max(e.worst, d);
    e.mean += d;
    ++e.compared;
  }
  if (e.compared > 0) e.mean /= double(e.compared);
  return e;
}

// The whole log through the builder (as its base class), through CNDTOnlineMapper by hand,
// and through MRPT's ICP builder with icp-slam's demo configuration: run once for the suite.
class MapBuilderOnSena : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!ndtom::testing::senaAvailable()) return;
    log_ = ndtom::testing::readSena();
    builder_ = std::make_unique<CMetricMapBuilderNDT>();
    builder_->NDT_options = shippedOptions();
    mrpt::slam::CMetricMapBuilder& base = *builder_;
    base.initialize();
    const auto start = std::chrono::steady_clock::now();
    for (const ActionFrame& p : log_) {
      base.processActionObservation(*p.actions, *p.frame);
      poses_.push_back(meanOf(base));
    }
    seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    oracle_ = std::make_unique<mrpt_ndtom::CNDTOnlineMapper>(builder_->NDT_options.mapOptions,
                                                             builder_->NDT_options.online);
    for (const ActionFrame& p : log_) {
      const auto scan = p.frame->getObservationByClass<mrpt::obs::CObservation2DRangeScan>();
      oracle_poses_.push_back(oracle_->processObservation(*scan, odometryOf(p)).mean);
    }
  }
  static void TearDownTestSuite() {
    builder_.reset();
    oracle_.reset();
  }
  void SetUp() override {
    if (!ndtom::testing::senaAvailable()) GTEST_SKIP() << "no SENA log (Debian's mrpt-common)";
  }

  static std::vector<ActionFrame> log_;
  static std::unique_ptr<CMetricMapBuilderNDT> builder_;
  static std::vector<CPose3D> poses_;
  static double seconds_;  // the builder's wall time on the whole log
  static std::unique_ptr<mrpt_ndtom::CNDTOnlineMapper> oracle_;
  static std::vector<CPose3D> oracle_poses_;
};
std::vector<ActionFrame> MapBuilderOnSena::log_;
std::unique_ptr<CMetricMapBuilderNDT> MapBuilderOnSena::builder_;
std::vector<CPose3D> MapBuilderOnSena::poses_;
double MapBuilderOnSena::seconds_ = 0;
std::unique_ptr<mrpt_ndtom::CNDTOnlineMapper> MapBuilderOnSena::oracle_;
std::vector<CPose3D> MapBuilderOnSena::oracle_poses_;

TEST_F(MapBuilderOnSena, GivesTheOnlineMappersPosesForTheSameScansAndOdometry) {
  ASSERT_EQ(log_.size(), 224u);
  ASSERT_EQ(poses_.size(), oracle_poses_.size());
  for (size_t i = 0; i < poses_.size(); ++i)
    ASSERT_TRUE(poses_[i].getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>() ==
                oracle_poses_[i].getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>())
        << "frame " << i << ": " << poses_[i] << " vs " << oracle_poses_[i];
}

TEST_F(MapBuilderOnSena, TracksEveryScanCloseToMrptsIcpSlamAndReferencePoses) {
  const auto steps = builder_->getSteps();
  ASSERT_EQ(steps.size(), log_.size());
  size_t lost = 0;
  double slowest = 0;
  std::string why;
  for (size_t i = 0; i < steps.size(); ++i) {
    if (steps[i].outcome == ndtom::OnlineOutcome::Lost)
      why += "frame " + std::to_string(i) + ": " + steps[i].why_lost + "\n";
    lost += steps[i].outcome == ndtom::OnlineOutcome::Lost;
    slowest = std::max(slowest, steps[i].seconds);
  }
  // One frame of this log stands at the verdict's edge: ndtom-slam on the same log places it
  // with a matched fraction of 0.28 (0.25 asked) after a 0.68 m correction of the odometry,
  // where people walk the corridor; here the pose found leaves 0.4 of it in free space.
  EXPECT_LE(lost, 1u) << why;

  // MRPT's ICP builder as icp-slam runs it (its demo configuration for this log).
  const mrpt::config::CConfigFile icp_ini(
      "/usr/share/mrpt/config_files/icp-slam/icp-slam_demo_classic.ini");
  mrpt::slam::CMetricMapBuilderICP icp;
  icp.setMinLoggingLevel(mrpt::system::LVL_WARN);  // a line per scan otherwise
  icp.ICP_options.loadFromConfigFile(icp_ini, "MappingApplication");
  icp.ICP_params.loadFromConfigFile(icp_ini, "ICP");
  icp.initialize();
  std::vector<CPose3D> icp_poses;
  const auto start = std::chrono::steady_clock::now();
  for (const ActionFrame& p : log_) {
    icp.processActionObservation(*p.actions, *p.frame);
    icp_poses.push_back(meanOf(icp));
  }
  const double icp_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  double worst_icp = 0;
  for (size_t i = 0; i < poses_.size(); ++i)
    worst_icp = std::max(worst_icp, distance2d(poses_[i], icp_poses[i]));
  // Measured: 0.08 m apart at the end, 0.56 m at most (where ICP itself is farthest from the
  // reference poses).
  const double final_gap = distance2d(poses_.back(), icp_poses.back());
  EXPECT_LT(final_gap, 0.2);
  EXPECT_LT(worst_icp, 0.8);

  // MRPT's reference poses of the log (99 of its frames, by time stamp): measured 0.43 m at
  // most, ICP's 0.52 m.
  const Errors ndt = referenceErrors(poses_, log_), by_icp = referenceErrors(icp_poses, log_);
  EXPECT_GE(ndt.compared, 90u);
  EXPECT_LT(ndt.worst, 0.6);

  const CPose3D& last = poses_.back();
  const CPose3D& icp_last = icp_poses.back();
  std::cout << "[ figures  ] " << steps.size() << " scans, " << lost << " lost; "
            << 1e3 * seconds_ / double(steps.size()) << " ms per scan (slowest " << 1e3 * slowest
            << " ms), ICP builder " << 1e3 * icp_seconds / double(steps.size())
            << " ms\n[ figures  ] final pose NDT (" << last.x() << ", " << last.y() << ", "
            << mrpt::RAD2DEG(last.yaw()) << " deg), ICP (" << icp_last.x() << ", " << icp_last.y()
            << ", " << mrpt::RAD2DEG(icp_last.yaw()) << " deg): " << final_gap << " m apart; worst "
            << worst_icp << " m\n[ figures  ] vs MRPT's reference poses (" << ndt.compared
            << "): NDT mean " << ndt.mean << " m, worst " << ndt.worst << " m; ICP mean "
            << by_icp.mean << " m, worst " << by_icp.worst << " m\n";
}

TEST_F(MapBuilderOnSena, StepsAgreeWithTheOdometry) {
  // Between consecutive scans the registered motion is the odometry's up to its errors,
  // never a jump. This log's odometry is late or early by a fraction of a step: its
  // corrections alternate in sign (scans 41, 42: +0.34 m, -0.32 m; measured worst 0.37 m
  // and 6.3°).
  double worst_m = 0, worst_deg = 0;
  for (size_t i = 1; i < poses_.size(); ++i) {
    const CPose3D registered = poses_[i] - poses_[i - 1];
    const CPose3D difference = registered - odometryOf(log_[i]);
    worst_m = std::max(worst_m, difference.translation().norm());
    worst_deg =
        std::max(worst_deg, std::abs(mrpt::RAD2DEG(mrpt::math::wrapToPi(difference.yaw()))));
  }
  EXPECT_LT(worst_m, 0.5);
  EXPECT_LT(worst_deg, 10.0);
  EXPECT_GT(worst_m, 0.0) << "the registration corrected nothing";
  // Planar: the 2D scans leave z, pitch and roll where the odometry puts them.
  for (const CPose3D& p : poses_) {
    EXPECT_NEAR(p.z(), 0.0, 1e-9);
    EXPECT_NEAR(p.pitch(), 0.0, 1e-9);
    EXPECT_NEAR(p.roll(), 0.0, 1e-9);
  }
}

TEST_F(MapBuilderOnSena, TheMetricMapIsTheMappersNdtOm) {
  const mrpt::maps::CMultiMetricMap* multi = builder_->getCurrentlyBuiltMetricMap();
  ASSERT_NE(multi, nullptr);
  ASSERT_EQ(multi->maps.size(), 1u);
  const auto ndt = multi->mapByClass<mrpt_ndtom::CNDTOccupancyMap>();
  ASSERT_TRUE(ndt);
  const auto expected = oracle_->map();
  EXPECT_EQ(ndt->ndtMap().numGaussians(), expected->ndtMap().numGaussians());
  EXPECT_EQ(ndt->ndtMap().numCells(), expected->ndtMap().numCells());
  EXPECT_GT(ndt->ndtMap().numGaussians(), 1000u);
  EXPECT_TRUE(ndt->insertionOptions == builder_->NDT_options.mapOptions);
  EXPECT_EQ(builder_->getCurrentlyBuiltMetricMap(), multi) << "the same object while unchanged";
}

TEST_F(MapBuilderOnSena, TheSimpleMapRebuildsTheMap) {
  mrpt::maps::CSimpleMap frames;
  builder_->getCurrentlyBuiltMap(frames);
  ASSERT_EQ(frames.size(), builder_->getCurrentlyBuiltMapSize());
  std::vector<size_t> inserted;  // the log's frames that are in the map
  const auto steps = builder_->getSteps();
  for (size_t i = 0; i < steps.size(); ++i)
    if (steps[i].outcome != ndtom::OnlineOutcome::Lost) inserted.push_back(i);
  ASSERT_EQ(frames.size(), inserted.size()) << "every scan placed is inserted";
  ASSERT_GE(frames.size() + 1, log_.size());
  for (size_t k = 0; k < frames.size(); ++k)
    EXPECT_EQ(frames.getAsPair(k).pose->getMeanVal(), poses_[inserted[k]]) << k;
  // CNDTOccupancyMap's own insertion at those poses: the same Gaussians up to points that
  // round into the neighbouring cell (the poses pass through CPose3D once more here).
  mrpt_ndtom::CNDTOccupancyMap rebuilt;
  rebuilt.insertionOptions = builder_->NDT_options.mapOptions;
  for (const auto& [pose, frame] : frames) {
    const CPose3D at = pose->getMeanVal();
    frame->insertObservationsInto(rebuilt, at);
  }
  const double built = double(oracle_->ndtMap().numGaussians());
  EXPECT_NEAR(double(rebuilt.ndtMap().numGaussians()), built, 0.01 * built);
}

TEST_F(MapBuilderOnSena, AnObservationOnlyLogIsMappedWithItsOdometryReadings) {
  // The same log as icp-slam's observation-only format: odometry readings, then the scan.
  // Oracle: CNDTOnlineMapper given the motion between consecutive readings.
  CMetricMapBuilderNDT builder;
  builder.NDT_options = shippedOptions();
  builder.initialize();
  mrpt_ndtom::CNDTOnlineMapper mapper(builder.NDT_options.mapOptions, builder.NDT_options.online);
  mrpt::poses::CPose2D reading;
  std::optional<CPose3D> previous;
  for (size_t i = 0; i < log_.size(); ++i) {
    const auto& move = *log_[i].actions->getBestMovementEstimation();
    reading = reading + move.poseChange->getMeanVal();
    auto odometry = mrpt::obs::CObservationOdometry::Create();
    odometry->odometry = reading;
    odometry->timestamp = move.timestamp;
    builder.processObservation(odometry);
    for (const auto& obs : *log_[i].frame) builder.processObservation(obs);

    const CPose3D now(reading);
    const CPose3D motion = previous ? now - *previous : CPose3D();
    previous = now;
    const auto scan = log_[i].frame->getObservationByClass<mrpt::obs::CObservation2DRangeScan>();
    const CPose3D expected = mapper.processObservation(*scan, motion).mean;
    ASSERT_TRUE(meanOf(builder).getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>() ==
                expected.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>())
        << i << ": " << meanOf(builder) << " vs " << expected;
  }
  // Rounding in the readings changes the recovery at scan 131, not where the loop ends.
  EXPECT_EQ(builder.getCurrentlyBuiltMapSize(), log_.size());
  EXPECT_LT(distance2d(meanOf(builder), poses_.back()), 0.05);
}

TEST_F(MapBuilderOnSena, WithoutOdometryItStillTracks) {
  // Scans alone: the mapper predicts with constant velocity.
  CMetricMapBuilderNDT builder;
  builder.NDT_options = shippedOptions();
  builder.initialize();
  for (const ActionFrame& p : log_)
    for (const auto& obs : *p.frame) builder.processObservation(obs);
  ASSERT_EQ(builder.getSteps().size(), log_.size());
  EXPECT_LT(distance2d(builder.getSteps().back().pose, poses_.back()), 0.3);
}

TEST_F(MapBuilderOnSena, InitializedWithAMapItGoesOnFromThere) {
  constexpr size_t kKept = 100;
  mrpt::maps::CSimpleMap all, first;
  builder_->getCurrentlyBuiltMap(all);
  for (size_t i = 0; i < kKept; ++i) first.insert(all.getAsPair(i));
  CMetricMapBuilderNDT builder;
  builder.NDT_options = shippedOptions();
  mrpt::slam::CMetricMapBuilder& base = builder;
  base.initialize(first);
  EXPECT_EQ(base.getCurrentlyBuiltMapSize(), kKept);
  EXPECT_EQ(meanOf(base), poses_[kKept - 1]);
  for (size_t i = kKept; i < log_.size(); ++i) {
    base.processActionObservation(*log_[i].actions, *log_[i].frame);
    // The frames' poses pass through CPose3D once more: measured 0.08 m at most.
    EXPECT_LT(distance2d(meanOf(base), poses_[i]), 0.15) << i;
  }
  size_t lost = 0;
  for (const auto& step : builder.getSteps()) lost += step.outcome == ndtom::OnlineOutcome::Lost;
  EXPECT_LE(lost, 1u);
  EXPECT_EQ(base.getCurrentlyBuiltMapSize(), log_.size() - lost);
  const size_t built = base.getCurrentlyBuiltMapSize();

  // Frames going back in time are refused, and the builder keeps its map.
  mrpt::maps::CSimpleMap backwards;
  for (size_t i = 2; i-- > 0;) backwards.insert(all.getAsPair(i));
  const CPose3D before = meanOf(base);
  EXPECT_THROW(base.initialize(backwards), std::exception);
  EXPECT_EQ(base.getCurrentlyBuiltMapSize(), built);
  EXPECT_EQ(meanOf(base), before);
}

TEST_F(MapBuilderOnSena, SavesATopViewOfTheMapAndThePath) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("ndtom_builder_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "estimate.png").string();
  builder_->saveCurrentEstimationToImage(file);
  mrpt::img::CImage image;
  ASSERT_TRUE(image.loadFromFile(file));
  size_t coloured = 0, black = 0;
  for (unsigned y = 0; y < image.getHeight(); ++y)
    for (unsigned x = 0; x < image.getWidth(); ++x) {
      const uint8_t* px = image.ptr<uint8_t>(x, y);
      const auto [low, high] = std::minmax({px[0], px[1], px[2]});
      coloured += high - low > 150;
      black += high < 50;
    }
  // The path, about 90 m long, is 2 px wide at 10 px/m; each occupied Gaussian is a dot.
  EXPECT_GT(coloured, 1000u);
  const ndtom::NdtMap& map = oracle_->ndtMap();
  size_t occupied = 0;
  map.forEachCell([&](const ndtom::CellView& c) { occupied += ndtom::isOccupiedGaussian(map, c); });
  EXPECT_GT(double(black), 0.5 * double(occupied));
  EXPECT_THROW(builder_->saveCurrentEstimationToImage((dir / "no" / "such.png").string()),
               std::exception);
  std::filesystem::remove_all(dir);
}

TEST(MapBuilder, MapsLidarScansIn3DWithOdometryFromActions) {
  // The shipped BALM lidar scans as if the sensor had moved 0.6 m and 6° more at each scan
  // (scan i's points M_i⁻¹·p), the truth P_0⁻¹·P_i·M_i; the actions carry the true motion
  // with 5 cm and 2° of error, in all six degrees of freedom.
  constexpr int kScans = 6;
  const auto poses = ndtom::testing::balmPoses();
  CMetricMapBuilderNDT builder;
  builder.NDT_options.mapOptions.resolution = 0.2;
  builder.NDT_options.mapOptions.scan.max_range = 30;
  builder.initialize();
  CPose3D motion, previous_truth;
  for (int i = 0; i < kScans; ++i) {
    if (i > 0) motion = motion + CPose3D(0.6, 0, 0, mrpt::DEG2RAD(6.0), 0, 0);
    const CPose3D truth = (poses[size_t(i)] - poses[0]) + motion;
    auto cloud = mrpt::maps::CSimplePointsMap::Create();
    const auto scan = ndtom::testing::balmScan(i);
    for (size_t k = 0; k < scan->size(); ++k) {
      float x, y, z;
      scan->getPoint(k, x, y, z);
      const auto p = (-motion).composePoint(mrpt::math::TPoint3D(x, y, z));
      cloud->insertPoint(float(p.x), float(p.y), float(p.z));
    }
    auto obs = mrpt::obs::CObservationPointCloud::Create();
    obs->pointcloud = cloud;
    obs->timestamp = mrpt::Clock::fromDouble(100.0 + i);
    mrpt::obs::CSensoryFrame frame;
    frame.insert(obs);
    mrpt::obs::CActionCollection actions;
    mrpt::obs::CActionRobotMovement3D move;
    move.poseChange.mean = (truth - previous_truth) + CPose3D(0.05, 0, 0, mrpt::DEG2RAD(2.0), 0, 0);
    actions.insert(move);
    builder.processActionObservation(actions, frame);
    previous_truth = truth;
    const CPose3D got = builder.getCurrentPoseEstimation()->getMeanVal();
    EXPECT_LT((got.translation() - truth.translation()).norm(), 0.05)
        << i << ": " << got << " vs " << truth;
    EXPECT_LT(std::abs(mrpt::math::wrapToPi(got.yaw() - truth.yaw())), mrpt::DEG2RAD(0.5)) << i;
  }
  const auto steps = builder.getSteps();
  ASSERT_EQ(steps.size(), size_t(kScans));
  for (const auto& step : steps) EXPECT_NE(step.outcome, ndtom::OnlineOutcome::Lost);
  EXPECT_GT(builder.getCurrentlyBuiltMetricMap()
                ->mapByClass<mrpt_ndtom::CNDTOccupancyMap>()
                ->ndtMap()
                .numGaussians(),
            1000u);
}

TEST(MapBuilder, SkipsWhatItCannotMapAndRefusesNothing) {
  CMetricMapBuilderNDT builder;
  builder.processObservation(mrpt::obs::CObservationImage::Create());
  EXPECT_TRUE(builder.getSteps().empty());
  EXPECT_EQ(builder.getCurrentlyBuiltMapSize(), 0u);
  EXPECT_THROW(builder.processObservation(nullptr), std::exception);
  const auto pose = builder.getCurrentPoseEstimation()->getMeanVal();
  EXPECT_EQ(pose, CPose3D());
  ASSERT_NE(builder.getCurrentlyBuiltMetricMap(), nullptr);
  EXPECT_TRUE(builder.getCurrentlyBuiltMetricMap()->isEmpty());
}

TEST(MapBuilder, StartsAtX0) {
  CMetricMapBuilderNDT builder;
  const mrpt::poses::CPosePDFGaussian x0(mrpt::poses::CPose2D(1, 2, 0.5));
  builder.initialize({}, &x0);
  EXPECT_EQ(builder.getCurrentPoseEstimation()->getMeanVal(),
            CPose3D(mrpt::poses::CPose2D(1, 2, 0.5)));
  if (!ndtom::testing::senaAvailable()) return;
  const auto log = ndtom::testing::readSena(1);
  builder.processActionObservation(*log[0].actions, *log[0].frame);
  EXPECT_EQ(builder.getCurrentPoseEstimation()->getMeanVal(),
            CPose3D(mrpt::poses::CPose2D(1, 2, 0.5)))
      << "the first scan is placed at x0";
  mrpt::maps::CSimpleMap one;
  builder.getCurrentlyBuiltMap(one);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_THROW(builder.initialize(one, &x0), std::exception) << "x0 with an initial map";
  EXPECT_EQ(builder.getCurrentlyBuiltMapSize(), 1u) << "unchanged by the refusal";
}

TEST(MapBuilder, InitializeRefusesBadOptionsNamingThem) {
  CMetricMapBuilderNDT builder;
  builder.NDT_options.online.target_radius = -1;
  try {
    builder.initialize();
    FAIL() << "no exception";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("target_radius"), std::string::npos) << e.what();
  }
}

}  // namespace
