// ndtom-map --octomap: the .bt file opens with OctoMap's own library, and its occupied and
// free voxels are exactly our occupied and free cells (read from the .ndtom of the same run).
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <set>
#include <tuple>

#include "mapper_run.h"
#include "ndtom/files/map_io.h"
#include "ndtom/map/map_queries.h"
#include "ndtom_apps/octomap_export.h"

using namespace mapper_test;

namespace {

using Cells = std::set<std::tuple<int, int, int>>;

// Occupied and free cells of our map, as OctoMap keys.
std::pair<Cells, Cells> ourCells(const ndtom::NdtMap& map) {
  Cells occupied, free;
  map.forEachCell([&](const ndtom::CellView& c) {
    const auto key = std::make_tuple(c.index.x + 32768, c.index.y + 32768, c.index.z + 32768);
    const ndtom::CellState s = ndtom::cellState(map, c);
    if (s == ndtom::CellState::Occupied) occupied.insert(key);
    if (s == ndtom::CellState::Free) free.insert(key);
  });
  return {occupied, free};
}

// Occupied and free leaves of the .bt at full depth (OctoMap prunes equal siblings).
std::pair<Cells, Cells> octomapCells(const std::string& path, double resolution) {
  octomap::OcTree tree(path);
  EXPECT_DOUBLE_EQ(tree.getResolution(), resolution);
  tree.expand();
  Cells occupied, free;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    EXPECT_EQ(it.getDepth(), tree.getTreeDepth());
    const octomap::OcTreeKey k = it.getKey();
    (tree.isNodeOccupied(*it) ? occupied : free).insert({k[0], k[1], k[2]});
  }
  return {occupied, free};
}

void expectSameVoxels(const TempDir& dir, const std::string& stem, double resolution) {
  const ndtom::NdtMap map = ndtom::loadMap((dir / (stem + ".ndtom")).string());
  const auto [occupied, free] = ourCells(map);
  const auto [bt_occupied, bt_free] = octomapCells((dir / (stem + ".bt")).string(), resolution);
  EXPECT_GT(occupied.size(), 1000u);
  EXPECT_TRUE(bt_occupied == occupied) << bt_occupied.size() << " vs " << occupied.size();
  EXPECT_TRUE(bt_free == free) << bt_free.size() << " vs " << free.size();
}

TEST(MapperOctomap, BtFileHoldsOurOccupiedAndFreeCells) {
  TempDir dir;
  const ProgramRun run = runMapper(quoted(kLidar) + " -o " + quoted((dir / "lidar").string()) +
                                       " --octomap --no-pictures --max-scans 4",
                                   dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err.find("done."), std::string::npos) << "OctoMap's debug output: " << run.err;
  EXPECT_NE(run.out.find("lidar.bt"), std::string::npos) << run.out;
  expectSameVoxels(dir, "lidar", 0.2);
}

TEST(MapperOctomap, RecursiveNdtCellsWithPointsAreOccupied) {
  TempDir dir;
  const ProgramRun run = runMapper(quoted(kLidar) + " -o " + quoted((dir / "rndt").string()) +
                                       " --octomap --no-pictures --max-scans 2 "
                                       "--occupancy-enabled false --resolution 0.5",
                                   dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  expectSameVoxels(dir, "rndt", 0.5);
}

TEST(MapperOctomap, CellsBeyondOctomapsRangeAreRefused) {
  ndtom::NdtMap map;  // 0.2 m: OctoMap reaches 6553.6 m
  ndtom::CellStats one;
  one.n = 1;
  ASSERT_TRUE(map.setCell({40000, 0, 0}, 1.0f, one));
  TempDir dir;
  try {
    ndtom::mapper::writeOctomapBinary(map, (dir / "far.bt").string());
    FAIL() << "a cell 8 km away was written";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("beyond OctoMap's range"), std::string::npos) << e.what();
  }
  // The last cell OctoMap can hold on the negative side is written.
  ndtom::NdtMap edge;
  ASSERT_TRUE(edge.setCell({-32768, 5, -3}, 1.0f, one));
  ndtom::mapper::writeOctomapBinary(edge, (dir / "edge.bt").string());
  const auto [occupied, free] = octomapCells((dir / "edge.bt").string(), 0.2);
  EXPECT_TRUE(occupied == Cells({{0, 32773, 32765}}));
  EXPECT_TRUE(free.empty());
}

}  // namespace
