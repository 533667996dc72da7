// The compact cell coding of .ndtom files (format version 2, map_codec_blocks.cpp): every cell
// comes back bit for bit, on a real lidar map and on edge cases; a loaded map merges and
// coarsens exactly as the original; damage at any byte is rejected cleanly; version 1 files
// still load.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <random>

#include "ndtom/files/map_io.h"
#include "ndtom_internal/crc32.h"
#include "support/lidar_scans.h"
#include "support/map_equality.h"

using Eigen::Vector3d;
using ndtom::CellIndex;
using ndtom::CellStats;
using ndtom::CellView;
using ndtom::MapOptions;
using ndtom::NdtMap;

namespace {

using ndtom::testing::expectBitIdentical;
using ndtom::testing::sameBits;

NdtMap roundTrip(const NdtMap& map) {
  const auto bytes = ndtom::encodeMap(map);
  return ndtom::decodeMap(bytes.data(), bytes.size(), "round trip");
}

void expectRoundTrip(const NdtMap& map, const char* what) {
  SCOPED_TRACE(what);
  const auto bytes = ndtom::encodeMap(map);
  const NdtMap loaded = ndtom::decodeMap(bytes.data(), bytes.size(), what);
  expectBitIdentical(map, loaded);
  EXPECT_EQ(ndtom::encodeMap(loaded), bytes);
}

std::vector<uint8_t> withCrc(std::vector<uint8_t> b) {
  const uint32_t crc = ndtom::crc32(b.data(), b.size() - 4);
  for (int i = 0; i < 4; ++i) b[b.size() - 4 + size_t(i)] = uint8_t(crc >> (8 * i));
  return b;
}

// The first `scans` of the lidar scans in tests/data, at 0.2 m, rays cut at 30 m.
NdtMap lidarMap(size_t first, size_t scans) {
  MapOptions o;
  o.resolution = 0.2;
  o.scan.max_range = 30;
  NdtMap map(o);
  const auto all = ndtom::testing::lidarScansInWorld(first + scans);
  for (size_t i = first; i < all.size(); ++i) map.insertScan(all[i].points, all[i].origin);
  return map;
}

CellStats threePoints() {
  return CellStats::fromPoints({{0.01, 0.02, -0.03}, {-0.05, 0.04, 0.01}, {0.02, 0, 0}});
}

}  // namespace

TEST(MapCodec, RealLidarMapRoundTripsBitForBitWithinEightBytesPerCell) {
  const NdtMap map = lidarMap(0, 4);
  ASSERT_GT(map.numGaussians(), 5000u);
  const auto bytes = ndtom::encodeMap(map);
  const double per_cell = double(bytes.size()) / double(map.numCells());
  std::printf("%zu cells, %zu bytes, %.2f B per cell\n", map.numCells(), bytes.size(), per_cell);
  EXPECT_LE(per_cell, 8.0);
  expectRoundTrip(map, "lidar");
}

// RCU merges are exact but not associative in floating point: a loaded map must hold the very
// same bits, and coarsening merge them in the same order (block order, whatever the hash
// table's history: factors 3 and 5 span blocks), for the very same maps to come out.
TEST(MapCodec, LoadedMapsMergeAndCoarsenExactlyAsTheOriginals) {
  const NdtMap a = lidarMap(0, 2), b = lidarMap(2, 2);
  const NdtMap la = roundTrip(a), lb = roundTrip(b);
  for (const int factor : {2, 3, 5}) {
    SCOPED_TRACE(factor);
    expectBitIdentical(a.coarsened(factor), la.coarsened(factor));
  }
  NdtMap merged = a, merged_loaded = la;
  merged.merge(b);
  merged_loaded.merge(lb);
  expectBitIdentical(merged, merged_loaded);
}

TEST(MapCodec, EmptyMapsRoundTrip) {
  expectRoundTrip(NdtMap(), "empty");
  MapOptions o;
  o.occupancy.enabled = false;
  expectRoundTrip(NdtMap(o), "empty, no occupancy");
}

TEST(MapCodec, OneCellRoundTrips) {
  NdtMap map;
  map.setCell({5, -7, 3}, 0.7f, threePoints());
  expectRoundTrip(map, "one cell");
  NdtMap free_cell;
  free_cell.setCell({-1, 0, 0}, -0.4f, {});
  expectRoundTrip(free_cell, "one free cell");
}

// Recursive NDT: every cell has log-odds 0, most have statistics.
TEST(MapCodec, GaussiansWithoutOccupancyRoundTrip) {
  MapOptions o;
  o.occupancy.enabled = false;
  o.resolution = 0.3;
  NdtMap map(o);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-3, 3);
  std::vector<Vector3d> pts;
  for (int i = 0; i < 3000; ++i) pts.emplace_back(u(rng), u(rng), 0.2 * u(rng));
  map.insertScan(pts, Vector3d(0, 0, 1));
  ASSERT_GT(map.numGaussians(), 100u);
  expectRoundTrip(map, "no occupancy");
}

// Every log-odds distinct: the dictionary would cost more than the floats, so they go raw.
TEST(MapCodec, AllDistinctLogOddsFallBackToRawFloats) {
  NdtMap map;
  const int cells = 2048;  // 4 full blocks
  for (int k = 0; k < cells; ++k)
    map.setCell({k % 16, (k / 16) % 16, k / 256}, -1.9f + 0.001f * float(k), {});
  const auto bytes = ndtom::encodeMap(map);
  const size_t header = ndtom::encodeMap(NdtMap()).size();
  // A dictionary would take 4 B per value plus a run header (>= 2 B) per cell.
  EXPECT_LT(bytes.size(), header + 4.2 * cells);
  expectRoundTrip(map, "distinct log-odds");
  // A few repeated values among them keep the dictionary.
  NdtMap mixed = map;
  for (int k = 0; k < 1500; ++k) mixed.setCell({k % 16, (k / 16) % 16, k / 256}, -0.5f, {});
  EXPECT_LT(ndtom::encodeMap(mixed).size(), bytes.size());
  expectRoundTrip(mixed, "mixed log-odds");
}

// Negative and extreme indices, blocks far apart, signed zeros, zero and saturated statistics.
TEST(MapCodec, EdgeCellsRoundTrip) {
  const int32_t top = (1 << 30) - 1;
  NdtMap map;
  CellStats one;
  one.n = 1;
  one.relative_mean = {0.05, -0.0, 0.1};
  one.scatter(1, 1) = -0.0;  // a zero by value, not by bits
  CellStats repeated =
      CellStats::fromPoints({{0.01, 0.01, 0.01}, {0.01, 0.01, 0.01}, {0.01, 0.01, 0.01}});
  ASSERT_TRUE(repeated.scatter.isZero(0));
  CellStats saturated = threePoints();
  saturated.n = UINT32_MAX;
  const std::vector<std::pair<CellIndex, CellStats>> cells = {
      {{0, 0, 0}, threePoints()},       {{-1, -1, -1}, one},         {{-8, 0, 7}, repeated},
      {{-top, top, 0}, saturated},      {{top, -top, -top}, {}},     {{-top, -top, -top}, one},
      {{top, top, top}, threePoints()}, {{1000, -5000, 123456}, {}}, {{-9, -9, -9}, {}}};
  for (const auto& [index, stats] : cells) map.setCell(index, stats.n ? 1.5f : -0.0f, stats);
  map.setCell({-10, -9, -9}, 0.0f, {});  // +0 beside -0: different bits, different values
  ASSERT_EQ(map.numCells(), cells.size() + 1);
  expectRoundTrip(map, "edge cells");
}

// A small file of every kind of cell: each truncation is refused; each changed byte is refused
// by the checksum, and with the checksum recomputed either refused or a map that saves and
// loads back identically.
TEST(MapCodec, DamageAtEveryByteIsRejectedOrHarmless) {
  NdtMap map;
  map.setCell({0, 0, 0}, 1.2f, threePoints());
  map.setCell({1, 0, 0}, -0.4f, {});
  map.setCell({2, 0, 0}, -0.4f, {});
  map.setCell({-3, 9, 0}, 0.3f, CellStats::fromPoints({{0.01, 0.02, 0.03}}));
  map.setCell({40, 0, -17}, -0.8f, {});
  const auto bytes = ndtom::encodeMap(map);
  ASSERT_LT(bytes.size(), 600u);
  for (size_t len = 0; len < bytes.size(); ++len)
    EXPECT_THROW(ndtom::decodeMap(bytes.data(), len, "cut"), ndtom::MapFormatError) << len;
  size_t loaded = 0;
  for (size_t at = 0; at < bytes.size(); ++at)
    for (const uint8_t x : {0x01, 0x10, 0x80, 0xFF}) {
      auto b = bytes;
      b[at] ^= x;
      EXPECT_THROW(ndtom::decodeMap(b.data(), b.size(), "changed"), ndtom::MapFormatError) << at;
      if (at + 4 >= bytes.size()) continue;  // the checksum itself
      b = withCrc(b);
      std::optional<NdtMap> m;
      try {
        m.emplace(ndtom::decodeMap(b.data(), b.size(), "changed"));
      } catch (const ndtom::MapFormatError&) {
        continue;
      }
      ++loaded;
      SCOPED_TRACE(at);
      expectBitIdentical(*m, roundTrip(*m));
    }
  std::printf("%zu of %zu changes with a valid checksum load\n", loaded, 4 * (bytes.size() - 4));
}

// Counts that lie about the bytes after them are refused before anything is allocated.
TEST(MapCodec, CountsAreCheckedAgainstTheBytesLeft) {
  NdtMap map;
  for (int k = 0; k < 40; ++k) map.setCell({k, -k, 2 * k}, k % 3 ? -0.4f : 0.9f, {});
  const auto bytes = ndtom::encodeMap(map);
  // After the options: u64 cells, u64 blocks, u8 coding (the empty map's file ends there).
  const size_t cells_at = ndtom::encodeMap(NdtMap()).size() - 4 - 17;
  auto expectRefused = [&](size_t at, uint64_t value, const std::string& why) {
    auto b = bytes;
    std::memcpy(&b[at], &value, 8);
    b = withCrc(b);
    try {
      ndtom::decodeMap(b.data(), b.size(), "lying count");
      FAIL() << value << " loaded";
    } catch (const ndtom::MapFormatError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  for (const uint64_t blocks : {uint64_t(1) << 20, uint64_t(1) << 62, ~uint64_t(0)})
    expectRefused(cells_at + 8, blocks, "exceeds the file size");
  for (const uint64_t cells : {uint64_t(1) << 40, ~uint64_t(0)})
    expectRefused(cells_at, cells, "exceeds its blocks");
  expectRefused(cells_at, map.numCells() + 1, "does not match");
  expectRefused(cells_at, map.numCells() - 1, "more cells than the cell count");
  // The block count's high half overlapping the checksum.
  std::vector<uint8_t> head(bytes.begin(), bytes.begin() + long(cells_at + 12));
  head.resize(head.size() + 4);
  head = withCrc(head);
  EXPECT_THROW(ndtom::decodeMap(head.data(), head.size(), "overlap"), ndtom::MapFormatError);
}

// Blocks come in ascending order, each once: a file naming a block twice (its cells twice) is
// refused. Made from two maps whose only difference is the second block's index, so the one
// differing byte is that index's delta, then set to 0 (the same block again).
TEST(MapCodec, ABlockNamedTwiceIsRefused) {
  const auto twoBlocks = [](int32_t second_z) {
    NdtMap map;
    map.setCell({1, 1, 1}, -0.4f, {});
    map.setCell({1, 1, 1 + 8 * second_z}, -0.4f, {});
    return ndtom::encodeMap(map);
  };
  const auto next = twoBlocks(1), further = twoBlocks(2);
  ASSERT_EQ(next.size(), further.size());
  std::vector<size_t> differ;
  for (size_t i = 0; i + 4 < next.size(); ++i)
    if (next[i] != further[i]) differ.push_back(i);
  ASSERT_EQ(differ.size(), 1u) << "the blocks' bytes differ elsewhere than the index";
  auto twice = next;
  twice[differ[0]] = 0;  // zigzag delta 0
  twice = withCrc(twice);
  try {
    const NdtMap loaded = ndtom::decodeMap(twice.data(), twice.size(), "block twice");
    FAIL() << "loaded with " << loaded.numCells() << " cells";
  } catch (const ndtom::MapFormatError& e) {
    EXPECT_NE(std::string(e.what()).find("out of order"), std::string::npos) << e.what();
  }
}

namespace {

// Version 1's cells, read here from the layout in map_io.h without the library.
struct V1Cell {
  float logodds;
  uint32_t n;
  double values[9];
};

std::map<CellIndex, V1Cell> parseVersion1(const std::vector<uint8_t>& f) {
  size_t at = 16;  // magic, version, option count
  uint32_t options;
  std::memcpy(&options, &f[12], 4);
  for (uint32_t k = 0; k < options; ++k) at += 1 + f[at] + 8;
  uint64_t count;
  std::memcpy(&count, &f[at], 8);
  at += 8;
  std::map<CellIndex, V1Cell> cells;
  for (uint64_t k = 0; k < count; ++k) {
    CellIndex c;
    std::memcpy(&c.x, &f[at], 4);
    std::memcpy(&c.y, &f[at + 4], 4);
    std::memcpy(&c.z, &f[at + 8], 4);
    V1Cell cell{};
    std::memcpy(&cell.logodds, &f[at + 12], 4);
    std::memcpy(&cell.n, &f[at + 16], 4);
    at += 20;
    if (cell.n > 0) {
      std::memcpy(cell.values, &f[at], 72);
      at += 72;
    }
    cells.emplace(c, cell);
  }
  EXPECT_EQ(at + 4, f.size());
  return cells;
}

}  // namespace

// tests/data/map-files/lidar_v1.ndtom was written by the last version-1 writer.
TEST(MapCodec, Version1FilesStillLoadBitForBit) {
  const std::string path = std::string(NDTOM_TEST_DATA_DIR) + "/map-files/lidar_v1.ndtom";
  std::ifstream in(path, std::ios::binary);
  const std::vector<uint8_t> file{std::istreambuf_iterator<char>(in),
                                  std::istreambuf_iterator<char>()};
  ASSERT_EQ(file.size(), 35625u);
  ASSERT_EQ(file[8], 1);
  const NdtMap map = ndtom::loadMap(path);
  EXPECT_EQ(map.numCells(), 844u);
  EXPECT_EQ(map.numGaussians(), 240u);
  EXPECT_EQ(map.options().resolution, 0.25);
  const auto cells = parseVersion1(file);
  ASSERT_EQ(cells.size(), map.numCells());
  size_t differ = 0;
  for (const auto& [index, c] : cells) {
    const auto v = map.cell(index);
    if (!v || !sameBits(&v->logodds, &c.logodds, 4) || (v->stats ? v->stats->n : 0) != c.n) {
      ++differ;
      continue;
    }
    if (c.n == 0) continue;
    const auto& s = v->stats->scatter;
    const auto& m = v->stats->relative_mean;
    const double got[9] = {m[0], m[1], m[2], s(0, 0), s(0, 1), s(0, 2), s(1, 1), s(1, 2), s(2, 2)};
    differ += !sameBits(got, c.values, sizeof(got));
  }
  EXPECT_EQ(differ, 0u);
  // Saved again: the current version, smaller, the same cells.
  const auto now = ndtom::encodeMap(map);
  EXPECT_EQ(now[8], ndtom::kMapFormatVersion);
  EXPECT_LT(now.size(), file.size() * 2 / 3);
  expectBitIdentical(map, ndtom::decodeMap(now.data(), now.size(), "resaved"));
}
