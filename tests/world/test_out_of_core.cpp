// Building out of core (out_of_core_map.h) through a drive in the procedural city: with a
// resident budget of a tenth of the map, tiles are spilled and read back, and the result is
// the map built in memory, bit for bit, in either file format.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "city_route.h"
#include "ndtom/files/map_io.h"
#include "ndtom/files/tiled_map_io.h"
#include "ndtom/scale/block_moves.h"
#include "ndtom/scale/out_of_core_map.h"
#include "simulated_lidar.h"
#include "support/map_equality.h"

namespace {

namespace fs = std::filesystem;
using namespace ndtom;

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(OutOfCoreMap, SpillsAndReloadsTilesAndBuildsTheInMemoryMap) {
  world::CityLayout layout;
  layout.blocks_x = layout.blocks_y = 3;
  const world::CityWorld city(layout);
  world::RouteSettings route;
  route.length = 700;
  route.step = 7;
  const auto poses = world::driveThrough(city, route);
  world::LidarModel lidar;
  lidar.rings = 12;
  lidar.azimuth_steps = 360;
  lidar.max_range = 40;

  MapOptions options;
  options.resolution = 0.4;
  options.scan.max_range = 30;
  NdtMap whole(options);
  std::vector<std::vector<Eigen::Vector3d>> scans;
  for (size_t i = 0; i < poses.size(); ++i) {
    auto points = world::simulateScan(city, lidar, poses[i], i);
    for (auto& p : points) p = poses[i] * p;
    whole.insertScan(points, poses[i].translation());
    scans.push_back(std::move(points));
  }
  ASSERT_GT(whole.numCells(), 50000u);

  const fs::path dir = fs::temp_directory_path() / ("ndtom_ooc_" + std::to_string(::getpid()));
  const uint64_t budget = whole.memoryBytes() / 10;
  {
    OutOfCoreMap ooc(options, budget, 2, (dir / "spill").string());
    for (size_t i = 0; i < poses.size(); ++i)
      ooc.insertScan(scans[i], poses[i].translation(), options.scan);
    const auto& s = ooc.stats();
    std::printf("map %zu B, budget %llu B, peak resident %zu B, %zu spills, %zu loads, %zu tiles out\n",
                whole.memoryBytes(), (unsigned long long)budget, s.peak_resident_bytes, s.spills,
                s.loads, ooc.spilledTiles());
    EXPECT_GT(s.spills, 20u);
    EXPECT_GT(ooc.spilledTiles(), 10u);
    EXPECT_LT(s.peak_resident_bytes, whole.memoryBytes() / 2);  // memory follows the window
    EXPECT_LT(ooc.resident().memoryBytes(), whole.memoryBytes() / 3);

    saveTiledMap(whole, (dir / "memory.tiles").string(), 2);
    ooc.saveTiled((dir / "ooc.tiles").string());
    EXPECT_EQ(readBytes(dir / "ooc.tiles"), readBytes(dir / "memory.tiles"));
    EXPECT_GT(ooc.spilledTiles(), 10u);  // saving left the spilled tiles where they were

    NdtMap& assembled = ooc.assemble();
    ndtom::testing::expectBitIdentical(whole, assembled);
    EXPECT_EQ(encodeMap(assembled), encodeMap(whole));
  }
  EXPECT_TRUE(fs::is_empty(dir / "spill"));  // spill files go with the map
  fs::remove_all(dir);
}

// Glitch points kilometres away make the scan's box billions of tiles (of 0.8 m): the tiles it
// meets are then found from what the map holds, not by visiting the box's tiles (which would
// not finish), and the map is the in-memory one.
TEST(OutOfCoreMap, AScanBoxFarLargerThanTheMapIsHandledByWhatTheMapHolds) {
  MapOptions options;
  options.resolution = 0.1;
  options.scan.max_range = 1e6;
  std::vector<Eigen::Vector3d> near, glitchy;
  for (int i = 0; i < 200; ++i) near.emplace_back(3.0 + 0.01 * i, -2.0 + 0.02 * i, 0.5);
  glitchy = near;
  glitchy.emplace_back(1200.0, -900.0, 60.0);  // 1.5 km: traced (under kMaxRayCells cells)
  glitchy.emplace_back(-1200.0, 900.0, -60.0);
  NdtMap whole(options);
  const fs::path dir = fs::temp_directory_path() / ("ndtom_ooc_far_" + std::to_string(::getpid()));
  {
    OutOfCoreMap ooc(options, 1 << 26, 1, (dir / "spill").string());
    for (int s = 0; s < 4; ++s) {
      const auto& points = s % 3 == 0 ? glitchy : near;
      const Eigen::Vector3d origin(0.3 * s, 0, 1.0);
      whole.insertScan(points, origin);
      ooc.insertScan(points, origin, options.scan);
    }
    ndtom::testing::expectBitIdentical(whole, ooc.assemble());
  }
  fs::remove_all(dir);
}

TEST(OutOfCoreMap, RejectsBadSizesAndMovesBlocksBothWays) {
  EXPECT_THROW(OutOfCoreMap(MapOptions{}, 0, 2, "/tmp"), std::invalid_argument);
  EXPECT_THROW(OutOfCoreMap(MapOptions{}, 1000, 0, "/tmp"), std::invalid_argument);
  NdtMap map;
  map.setCell({0, 0, 0}, 1.0f, {});
  map.setCell({20, 0, 0}, -1.0f, {});
  const size_t before = map.memoryBytes();
  NdtMap far = ndtom::extractBlocks(map, [](const CellIndex& b) { return b.x > 0; });
  EXPECT_EQ(map.numCells(), 1u);
  EXPECT_EQ(far.numCells(), 1u);
  EXPECT_TRUE(far.cell({20, 0, 0}));
  EXPECT_THROW(ndtom::absorbBlocks(map, NdtMap(map)), std::invalid_argument);  // a block in both
  ndtom::absorbBlocks(map, std::move(far));
  EXPECT_EQ(map.numCells(), 2u);
  EXPECT_EQ(map.cell({20, 0, 0})->logodds, -1.0f);
  EXPECT_LE(map.memoryBytes(), before);
}

}  // namespace
