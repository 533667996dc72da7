// An MRPT rawlog (Debian's mrpt-common: 225 SICK scans with odometry, actions + sensory
// frames). The oracle walks the log with MRPT's own CRawlog, composes the odometry and
// inserts each scan with the plugin's CMetricMap::insertObservation; ndtom-map must give the
// same map from the odometry, and the same from a trajectory file in KITTI (line by line)
// or TUM format (matched by time stamp).
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <cstdio>

#include "mapper_run.h"
#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom/files/map_io.h"
#include "ndtom_io/pose_file.h"

using namespace mapper_test;
using mrpt::poses::CPose3D;

namespace {

constexpr size_t kScans = 100;  // of 225: keeps the test fast

struct LogScan {
  mrpt::obs::CObservation::Ptr observation;
  CPose3D pose;  ///< odometry; the origin before the first action
  double time = 0;
  bool after_an_action = false;  ///< false: MRPT's own readers skip it, as ndtom-map does
};

// Every 2D scan of the log, in order, with the odometry composed from its actions: MRPT's
// in-memory CRawlog, entry by entry.
std::vector<LogScan> readLog() {
  mrpt::obs::CRawlog log;
  EXPECT_TRUE(log.loadFromRawLogFile(kSenaRawlog)) << "needs Debian's mrpt-common";
  std::vector<LogScan> scans;
  CPose3D pose;
  bool moved = false;
  for (size_t i = 0; i < log.size(); ++i) {
    if (log.getType(i) == mrpt::obs::CRawlog::etActionCollection) {
      if (auto move = log.getAsAction(i)->getActionByClass<mrpt::obs::CActionRobotMovement2D>())
        pose = pose + CPose3D(move->poseChange->getMeanVal());
      moved = true;
    } else if (log.getType(i) == mrpt::obs::CRawlog::etSensoryFrame) {
      for (const auto& obs : *log.getAsObservations(i))
        if (IS_CLASS(*obs, mrpt::obs::CObservation2DRangeScan))
          scans.push_back({obs, pose, mrpt::Clock::toDouble(obs->timestamp), moved});
    }
  }
  return scans;
}

// The plugin's own insertion of the first `count` scans that `use` accepts.
template <class Use>
std::string expectedMap(const std::vector<LogScan>& scans, size_t count, Use use) {
  mrpt_ndtom::CNDTOccupancyMap map;
  for (const auto& s : scans)
    if (count > 0 && use(s)) {
      map.insertObservation(*s.observation, s.pose);
      --count;
    }
  const auto bytes = ndtom::encodeMap(map.ndtMap());
  return std::string(bytes.begin(), bytes.end());
}

void writeKitti(const std::vector<LogScan>& scans, const fs::path& path) {
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& s : scans) {
    const auto m = s.pose.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
    Eigen::Isometry3d pose;
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 4; ++col) pose.matrix()(row, col) = m(row, col);
    pose.makeAffine();
    poses.push_back(pose);
  }
  ndtom::io::writeKittiPoseFile(path.string(), poses);
}

void writeTum(const std::vector<LogScan>& scans, const fs::path& path) {
  FILE* f = std::fopen(path.string().c_str(), "w");
  std::fprintf(f, "# timestamp tx ty tz qx qy qz qw\n");
  for (const auto& s : scans) {
    mrpt::math::CQuaternionDouble q;
    s.pose.getAsQuaternion(q);
    std::fprintf(f, "%.6f %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", s.time, s.pose.x(),
                 s.pose.y(), s.pose.z(), q.x(), q.y(), q.z(), q.r());
  }
  std::fclose(f);
}

ndtom::NdtMap runOnLog(const TempDir& dir, const std::string& stem, const std::string& extra) {
  const ProgramRun run = runMapper(quoted(kSenaRawlog) + " -o " + quoted((dir / stem).string()) +
                                       " --max-scans " + std::to_string(kScans) + " " + extra,
                                   dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return ndtom::loadMap((dir / (stem + ".ndtom")).string());
}

std::string bytesOf(const ndtom::NdtMap& map) {
  const auto bytes = ndtom::encodeMap(map);
  return std::string(bytes.begin(), bytes.end());
}

ndtom::NdtMap decode(const std::string& bytes) {
  return ndtom::decodeMap(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
}

bool afterAnAction(const LogScan& s) {
  return s.after_an_action;
}
bool any(const LogScan&) {
  return true;
}

}  // namespace

TEST(MapperRawlog, OdometryGivesMrptsOwnMapAndAPlausibleOne) {
  TempDir dir;
  const std::vector<LogScan> scans = readLog();
  ASSERT_EQ(scans.size(), 225u);
  ASSERT_FALSE(scans[0].after_an_action);  // the log opens with a sensory frame
  const ndtom::NdtMap map = runOnLog(dir, "odometry", "");
  EXPECT_TRUE(sameBytes(bytesOf(map), expectedMap(scans, kScans, afterAnAction)));

  // Plausible: a 2D laser at a fixed height sees walls (Gaussians) through free space.
  EXPECT_GT(map.numGaussians(), 1000u);
  size_t occupied = 0, free = 0;
  map.forEachCell([&](const ndtom::CellView& c) { (c.logodds > 0 ? occupied : free) += 1; });
  EXPECT_GT(free, 5 * occupied);
  double z_min = 1e9, z_max = -1e9;
  map.forEachGaussian([&](const ndtom::Gaussian& g) {
    z_min = std::min(z_min, g.mean.z());
    z_max = std::max(z_max, g.mean.z());
  });
  EXPECT_LT(z_max - z_min, 1e-6);  // every point at the laser's height
  const std::string summary = readText(dir / "odometry.summary.json");
  EXPECT_EQ(jsonNumber(summary, "scans"), double(kScans));
  EXPECT_EQ(jsonNumber(summary, "scans_without_pose"), 1);
}

TEST(MapperRawlog, TrajectoryFilesGiveThePluginsMap) {
  TempDir dir;
  const std::vector<LogScan> scans = readLog();
  writeKitti(scans, dir / "poses.kitti.txt");
  writeTum(scans, dir / "poses.tum.txt");
  // With a trajectory every scan has a pose, the first one too.
  const ndtom::NdtMap expected = decode(expectedMap(scans, kScans, any));
  // KITTI files are re-orthonormalised on reading and TUM quaternions round the rotation:
  // poses change by ~1e-16, so a point on a cell border may change sides. Allow 0.5% of
  // the cells and Gaussians to differ.
  for (const std::string format : {"kitti", "tum"}) {
    SCOPED_TRACE(format);
    const ndtom::NdtMap map =
        runOnLog(dir, format,
                 "--no-pictures --poses " + quoted((dir / ("poses." + format + ".txt")).string()));
    const double cells = double(expected.numCells()), gaussians = double(expected.numGaussians());
    EXPECT_NEAR(double(map.numCells()), cells, 0.005 * cells);
    EXPECT_NEAR(double(map.numGaussians()), gaussians, 0.005 * gaussians);
    size_t shared = 0;
    expected.forEachCell([&](const ndtom::CellView& c) { shared += map.cell(c.index) ? 1 : 0; });
    EXPECT_GT(double(shared), 0.995 * cells);
  }
}
