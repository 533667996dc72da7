// Memory follows the environment, not the trajectory (the paper's claim): replaying the same
// real scans again and again leaves the number of cells and the map's memory where the first
// pass left them (within 1 %).
#include <gtest/gtest.h>

#include "ndtom/map/ndt_map.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

TEST(MemoryBounded, RepeatedPassesOverTheSameScansDoNotGrowTheMap) {
  const std::string dir = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld/";
  const auto poses = ndtom::io::readPoseFile(dir + "poses.txt");
  std::vector<std::vector<Eigen::Vector3d>> scans;
  for (size_t i = 0; i < poses.size(); ++i) {
    auto cloud = ndtom::io::readPcd(dir + "full" + std::to_string(i) + ".pcd");
    for (auto& p : cloud.points) p = poses[i].pose * p;
    scans.push_back(std::move(cloud.points));
  }
  ndtom::MapOptions o;
  o.resolution = 0.4;
  o.scan.max_range = 30;
  o.scan.ray_mode = ndtom::RayMode::PerHitCell;
  ndtom::NdtMap map(o);
  size_t first_cells = 0, first_bytes = 0;
  for (int pass = 0; pass < 5; ++pass) {
    for (size_t i = 0; i < scans.size(); ++i) map.insertScan(scans[i], poses[i].pose.translation());
    if (pass == 0) {
      first_cells = map.numCells();
      first_bytes = map.memoryBytes();
      continue;
    }
    // Cells are never forgotten, and no new ones appear: the scans see the same space.
    EXPECT_EQ(map.numCells(), first_cells) << "pass " << pass;
    EXPECT_LE(double(map.memoryBytes()), 1.01 * double(first_bytes)) << "pass " << pass;
  }
  EXPECT_GT(first_cells, 10000u);
}
