// Multi-threaded insertion (ScanOptions::threads) splits every stage of a scan update over
// threads. On real lidar scans, any thread count must give the same map, byte for byte in the
// file format, and the same insertion report. Also built with ThreadSanitizer (see
// CMakeLists.txt), so a data race between the stages' threads fails the test.
#include <gtest/gtest.h>

#include "ndtom/files/map_io.h"
#include "ndtom/map/ndt_map.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

using Eigen::Vector3d;

namespace {

struct Scan {
  std::vector<Vector3d> points;
  Vector3d origin;
};

std::vector<Scan> realScans(int count) {
  const std::string dir = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld/";
  const auto poses = ndtom::io::readPoseFile(dir + "poses.txt");
  std::vector<Scan> scans;
  for (int i = 0; i < count; ++i) {
    auto cloud = ndtom::io::readPcd(dir + "full" + std::to_string(i) + ".pcd");
    for (auto& p : cloud.points) p = poses[i].pose * p;
    scans.push_back({cloud.points, poses[i].pose.translation()});
  }
  // Bad points among good ones: rejected the same way whatever the thread count.
  scans[1].points[7] = Vector3d(std::nan(""), 0, 0);
  scans[1].points[8] = scans[1].origin;
  return scans;
}

}  // namespace

TEST(ParallelInsertion, AnyThreadCountGivesTheSameMapAndReports) {
  const std::vector<Scan> scans = realScans(3);
  for (const auto mode : {ndtom::RayMode::PerPoint, ndtom::RayMode::PerHitCell}) {
    ndtom::MapOptions o;
    o.resolution = 0.2;
    o.scan.max_range = 20;  // some rays truncated
    o.scan.ray_mode = mode;
    std::vector<uint8_t> reference_file, reference_coarse;
    std::vector<std::string> reference_reports;
    std::vector<ndtom::CellIndex> reference_order;
    for (const int threads : {1, 2, 3}) {
      o.scan.threads = threads;
      ndtom::NdtMap map(o);
      std::vector<std::string> reports;
      for (const Scan& s : scans) reports.push_back(map.insertScan(s.points, s.origin).toString());
      const std::vector<uint8_t> file = ndtom::encodeMap(map);
      // Blocks are created in the same order too: unordered iteration, and what depends on
      // it (a coarse cell merges its fine cells in that order), do not change either.
      std::vector<ndtom::CellIndex> order;
      map.forEachCell([&](const ndtom::CellView& c) { order.push_back(c.index); });
      const std::vector<uint8_t> coarse = ndtom::encodeMap(map.coarsened(3));
      if (threads == 1) {
        reference_file = file;
        reference_reports = reports;
        reference_order = order;
        reference_coarse = coarse;
        ASSERT_GT(map.numGaussians(), 1000u);
        continue;
      }
      EXPECT_EQ(file, reference_file) << threads << " threads";
      EXPECT_EQ(reports, reference_reports) << threads << " threads";
      EXPECT_TRUE(order == reference_order) << threads << " threads";
      EXPECT_EQ(coarse, reference_coarse) << threads << " threads";
    }
  }
}
