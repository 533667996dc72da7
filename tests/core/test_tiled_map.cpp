// Maps stored as tiles (tiled_map.h): all tiles together are the map bit for bit; a region
// loads exactly the cells of the tiles it meets (found here from the cells' positions); any
// damaged or cut byte is refused; a tile under the wrong key is caught.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

#include "ndtom/files/tiled_map_io.h"
#include "ndtom/map/block_grid.h"
#include "ndtom_internal/crc32.h"
#include "support/lidar_scans.h"
#include "support/map_equality.h"

using ndtom::CellIndex;
using ndtom::CellStats;
using ndtom::CellView;
using ndtom::NdtMap;
using ndtom::testing::expectBitIdentical;
namespace fs = std::filesystem;

namespace {

struct TempFile {
  fs::path path = fs::temp_directory_path() /
                  ("ndtom_tiles_" + std::to_string(::getpid()) + "_" + std::to_string(count++));
  ~TempFile() { fs::remove(path); }
  static inline int count = 0;
};

NdtMap lidarMap() {
  ndtom::MapOptions o;
  o.resolution = 0.2;
  o.scan.max_range = 30;
  NdtMap map(o);
  for (const auto& s : ndtom::testing::lidarScansInWorld(3)) map.insertScan(s.points, s.origin);
  return map;
}

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}
void writeBytes(const fs::path& p, const std::string& b) {
  std::ofstream(p, std::ios::binary | std::ios::trunc) << b;
}

NdtMap smallMap() {
  NdtMap map;
  const CellStats three =
      CellStats::fromPoints({{0.01, 0.02, -0.03}, {-0.05, 0.04, 0.01}, {0.02, 0, 0}});
  map.setCell({0, 0, 0}, 1.2f, three);
  map.setCell({9, 0, 0}, -0.4f, {});
  map.setCell({-3, 9, 0}, 0.3f, CellStats::fromPoints({{0.01, 0.02, 0.03}}));
  map.setCell({40, 0, -17}, -0.8f, {});
  return map;
}

}  // namespace

TEST(TiledMap, AllTilesTogetherAreTheMapBitForBit) {
  const NdtMap map = lidarMap();
  ASSERT_GT(map.numCells(), 100000u);
  for (const int tile_blocks : {1, 4, 16}) {
    SCOPED_TRACE(tile_blocks);
    TempFile f;
    ndtom::saveTiledMap(map, f.path.string(), tile_blocks);
    const ndtom::TiledMapFile file(f.path.string());
    EXPECT_EQ(file.tileBlocks(), tile_blocks);
    uint64_t cells = 0;
    for (const auto& t : file.tiles()) cells += t.cells;
    EXPECT_EQ(cells, map.numCells());
    EXPECT_GT(file.tiles().size(), tile_blocks == 16 ? 4u : 40u);
    expectBitIdentical(map, file.loadAll());
    // The tiles cost little next to one map file: headers and index.
    const double overhead = double(fs::file_size(f.path)) / double(ndtom::encodeMap(map).size());
    EXPECT_LT(overhead, tile_blocks == 1 ? 1.6 : 1.1) << overhead;
  }
}

TEST(TiledMap, RegionLoadsTheCellsOfTheTilesItMeets) {
  const NdtMap map = lidarMap();
  TempFile f;
  ndtom::saveTiledMap(map, f.path.string(), 4);
  const ndtom::TiledMapFile file(f.path.string());
  const double edge = 4 * ndtom::kBlockEdge * 0.2;
  EXPECT_DOUBLE_EQ(file.tileEdgeMetres(), edge);
  const Eigen::AlignedBox3d region(Eigen::Vector3d(-5, -3, -1), Eigen::Vector3d(4, 6, 2));
  const NdtMap part = file.loadRegion(region);
  // Independently: a cell belongs if the tile-sized cube holding its centre meets the region.
  NdtMap expected(map.options());
  map.forEachCellOrdered([&](const CellView& c) {
    const Eigen::Vector3d centre = map.geometry().cellCenter(c.index);
    const Eigen::Vector3d lo = (centre / edge).array().floor() * edge;
    if (Eigen::AlignedBox3d(lo, lo + Eigen::Vector3d::Constant(edge)).intersects(region))
      expected.setCell(c.index, c.logodds, c.stats ? *c.stats : CellStats{});
  });
  ASSERT_GT(expected.numCells(), 1000u);
  ASSERT_LT(expected.numCells(), map.numCells());
  expectBitIdentical(expected, part);
  // A region far away loads nothing.
  EXPECT_TRUE(file.loadRegion({Eigen::Vector3d::Constant(1e5), Eigen::Vector3d::Constant(1e5 + 1)})
                  .isEmpty());
}

TEST(TiledMap, DamageOrACutAtAnyByteIsRefused) {
  const NdtMap map = smallMap();
  TempFile f, g;
  ndtom::saveTiledMap(map, f.path.string(), 1);
  const std::string bytes = readBytes(f.path);
  ASSERT_EQ(ndtom::TiledMapFile(f.path.string()).tiles().size(), 4u);
  const auto refused = [&](const std::string& b) {
    writeBytes(g.path, b);
    try {
      ndtom::TiledMapFile(g.path.string()).loadAll();
    } catch (const std::runtime_error&) {  // MapFormatError included
      return true;
    }
    return false;
  };
  for (size_t len = 0; len < bytes.size(); ++len) EXPECT_TRUE(refused(bytes.substr(0, len))) << len;
  // Every byte is under a checksum: the index's or a tile's.
  for (size_t at = 0; at < bytes.size(); ++at)
    for (const uint8_t x : {0x01, 0x80}) {
      std::string b = bytes;
      b[at] = char(uint8_t(b[at]) ^ x);
      EXPECT_TRUE(refused(b)) << at;
    }
}

TEST(TiledMap, ATileUnderAnotherKeyIsCaught) {
  TempFile f;
  ndtom::saveTiledMap(smallMap(), f.path.string(), 1);
  std::string b = readBytes(f.path);
  const auto u64At = [&](size_t at) {
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= uint64_t(uint8_t(b[at + size_t(i)])) << (8 * i);
    return v;
  };
  // The first index entry's x, moved far from every other tile, and the index checksum (over
  // the header, the index and the index's offset) made right again.
  const size_t index_at = size_t(u64At(b.size() - 12));
  b[index_at + 8] = char(uint8_t(b[index_at + 8]) + 7);
  const std::string header = b.substr(0, 24 + size_t(u64At(16)));
  const std::string index = b.substr(index_at, b.size() - 4 - index_at);
  const uint32_t crc =
      ndtom::crc32(index.data(), index.size(), ndtom::crc32(header.data(), header.size()));
  for (int i = 0; i < 4; ++i) b[b.size() - 4 + size_t(i)] = char(uint8_t(crc >> (8 * i)));
  writeBytes(f.path, b);
  const ndtom::TiledMapFile file(f.path.string());  // the index itself is consistent
  EXPECT_THROW(file.loadAll(), ndtom::MapFormatError);
}

TEST(TiledMap, TilesAddOnlyToUnknownCells) {
  const NdtMap map = smallMap();
  TempFile f;
  ndtom::saveTiledMap(map, f.path.string(), 1);
  const ndtom::TiledMapFile file(f.path.string());
  NdtMap resident = file.loadTile(file.tiles()[0]);
  EXPECT_THROW(ndtom::TiledMapFile::addTile(file.loadTile(file.tiles()[0]), resident),
               std::invalid_argument);
  ndtom::TiledMapFile::addTile(file.loadTile(file.tiles()[1]), resident);
  EXPECT_EQ(resident.numCells(), file.tiles()[0].cells + file.tiles()[1].cells);
  EXPECT_THROW(ndtom::saveTiledMap(map, f.path.string(), 0), std::invalid_argument);
}
