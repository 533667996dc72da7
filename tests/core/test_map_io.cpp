// The .ndtom file format: exact round trips, and every damaged file rejected cleanly.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>

#include "ndtom/files/map_io.h"
#include "ndtom_internal/atomic_file.h"
#include "ndtom_internal/crc32.h"

using Eigen::Vector3d;
using ndtom::MapOptions;
using ndtom::NdtMap;

namespace {

NdtMap sampleMap() {
  MapOptions o;
  o.resolution = 0.35;
  o.occupancy.p_hit = 0.7;
  o.scan.max_range = 8.0;
  o.scan.ray_mode = ndtom::RayMode::PerHitCell;
  NdtMap map(o);
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-4, 4);
  for (int s = 0; s < 4; ++s) {
    std::vector<Vector3d> pts;
    for (int i = 0; i < 300; ++i) pts.emplace_back(u(rng), u(rng), i % 2 ? -1.0 : u(rng));
    map.insertScan(pts, Vector3d(0.1 * s, 0, 0.5));
  }
  return map;
}

// A few hundred bytes with every kind of record: free cells, cells with 1-2 points, Gaussians.
NdtMap smallMap() {
  MapOptions o;
  o.resolution = 0.5;
  NdtMap map(o);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0.01, 0.49);
  map.insertScan({{2 + u(rng), u(rng), u(rng)},
                  {2 + u(rng), u(rng), u(rng)},
                  {2 + u(rng), u(rng), u(rng)},
                  {1 + u(rng), 1 + u(rng), u(rng)}},
                 Vector3d(0.2, 0.2, 0.2));
  return map;
}

void expectIdentical(const NdtMap& a, const NdtMap& b) {
  ASSERT_EQ(a.numCells(), b.numCells());
  EXPECT_EQ(a.options().resolution, b.options().resolution);
  EXPECT_EQ(a.options().occupancy.p_hit, b.options().occupancy.p_hit);
  EXPECT_EQ(a.options().scan.max_range, b.options().scan.max_range);
  EXPECT_EQ(a.options().scan.ray_mode, b.options().scan.ray_mode);
  a.forEachCell([&](const ndtom::CellView& ca) {
    const auto cb = b.cell(ca.index);
    ASSERT_TRUE(cb);
    EXPECT_EQ(ca.logodds, cb->logodds);
    ASSERT_EQ(ca.stats == nullptr, cb->stats == nullptr);
    if (!ca.stats) return;
    EXPECT_EQ(ca.stats->n, cb->stats->n);
    EXPECT_EQ(ca.stats->relative_mean, cb->stats->relative_mean);
    EXPECT_EQ(ca.stats->scatter, cb->stats->scatter);
  });
}

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          (name + "-" + std::to_string(::getpid()) + ".ndtom"))
      .string();
}

}  // namespace

TEST(MapIo, SaveLoadRoundTripIsExact) {
  const NdtMap map = sampleMap();
  ASSERT_GT(map.numGaussians(), 10u);
  const std::string path = tempPath("roundtrip");
  ndtom::saveMap(map, path);
  const NdtMap loaded = ndtom::loadMap(path);
  expectIdentical(map, loaded);
  EXPECT_EQ(ndtom::encodeMap(loaded), ndtom::encodeMap(map));
  std::remove(path.c_str());
}

// setCell grows a block's statistics one cell at a time; a loaded map keeps no spare room
// (shrinking it again frees nothing), while the same cells set by hand leave some.
TEST(MapIo, LoadedMapKeepsNoSpareStatisticsRoom) {
  const NdtMap map = sampleMap();
  NdtMap by_hand(map.options());
  map.forEachCell([&](const ndtom::CellView& c) {
    by_hand.setCell(c.index, c.logodds, c.stats ? *c.stats : ndtom::CellStats{});
  });
  const size_t grown = by_hand.memoryBytes();
  by_hand.shrinkToFit();
  ASSERT_LT(by_hand.memoryBytes(), grown);  // the check below can see spare room

  // Not through a copy: copying a map drops spare room by itself.
  auto expectNoSpareRoom = [](NdtMap&& m, const char* what) {
    const size_t bytes = m.memoryBytes();
    m.shrinkToFit();
    EXPECT_EQ(m.memoryBytes(), bytes) << what;
  };
  const std::vector<uint8_t> file = ndtom::encodeMap(map);
  for (const NdtMap* m : {&map, &std::as_const(by_hand)})
    EXPECT_EQ(m->memoryBytes(), m->memoryBytesCounted());
  expectNoSpareRoom(ndtom::decodeMap(file.data(), file.size()), "loaded");
  expectNoSpareRoom(map.coarsened(2), "coarsened");
  NdtMap merged(map.options());
  merged.merge(map);
  expectNoSpareRoom(std::move(merged), "merged");
}

TEST(MapIo, EmptyMapRoundTrips) {
  const NdtMap empty;
  const auto bytes = ndtom::encodeMap(empty);
  const NdtMap loaded = ndtom::decodeMap(bytes.data(), bytes.size());
  EXPECT_TRUE(loaded.isEmpty());
}

TEST(MapIo, FileIsLittleEndianWithMagicAndVersion) {
  const auto bytes = ndtom::encodeMap(sampleMap());
  ASSERT_GT(bytes.size(), 12u);
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 8), "NDTOMMAP");
  EXPECT_EQ(bytes[8], ndtom::kMapFormatVersion);
  EXPECT_EQ(bytes[9] | bytes[10] | bytes[11], 0);
}

TEST(MapIo, EveryTruncationIsRejected) {
  const NdtMap map = smallMap();
  ASSERT_EQ(map.numGaussians(), 1u);
  const auto bytes = ndtom::encodeMap(map);
  for (size_t len = 0; len < bytes.size(); ++len) {
    EXPECT_THROW(ndtom::decodeMap(bytes.data(), len, "truncated"), ndtom::MapFormatError)
        << "length " << len;
  }
}

TEST(MapIo, RandomByteFlipsAreRejected) {
  const auto bytes = ndtom::encodeMap(sampleMap());
  std::mt19937 rng(1);
  std::uniform_int_distribution<size_t> pos(0, bytes.size() - 1);
  std::uniform_int_distribution<int> bit(0, 7);
  for (int trial = 0; trial < 2000; ++trial) {
    auto damaged = bytes;
    const int flips = 1 + trial % 4;
    for (int f = 0; f < flips; ++f) damaged[pos(rng)] ^= uint8_t(1u << bit(rng));
    if (damaged == bytes) continue;
    EXPECT_THROW(ndtom::decodeMap(damaged.data(), damaged.size(), "flipped"),
                 ndtom::MapFormatError);
  }
}

// Damage with a recomputed checksum: the structural checks alone must catch it.
TEST(MapIo, ValidChecksumButBadContentIsRejected) {
  const NdtMap map = smallMap();
  ASSERT_EQ(map.numGaussians(), 1u);
  const auto original = ndtom::encodeMap(map);
  auto withCrc = [](std::vector<uint8_t> b) {
    const uint32_t crc = ndtom::crc32(b.data(), b.size() - 4);
    for (int i = 0; i < 4; ++i) b[b.size() - 4 + i] = uint8_t(crc >> (8 * i));
    return b;
  };
  auto expectRejected = [&](std::vector<uint8_t> b, const char* what) {
    b = withCrc(std::move(b));
    EXPECT_THROW(ndtom::decodeMap(b.data(), b.size(), what), ndtom::MapFormatError) << what;
  };
  auto b = original;
  b[8] = uint8_t(ndtom::kMapFormatVersion + 1);
  expectRejected(b, "future version");
  b[8] = 0;
  expectRejected(b, "version 0");
  // Every byte of the body, in turn, set to 0xFF: huge counts, NaNs, out-of-range values.
  size_t accepted = 0;
  for (size_t i = 12; i + 4 < original.size(); ++i) {
    b = original;
    b[i] = 0xFF;
    b = withCrc(b);
    std::optional<ndtom::NdtMap> loaded;
    try {
      loaded.emplace(ndtom::decodeMap(b.data(), b.size(), "poked"));
    } catch (const ndtom::MapFormatError&) {
      continue;
    }
    // A change that still loads (a low mantissa byte, another valid cell index) gives a map
    // that saves and loads back identically: nothing accepted is unwritable.
    ++accepted;
    const auto saved = ndtom::encodeMap(*loaded);
    expectIdentical(*loaded, ndtom::decodeMap(saved.data(), saved.size(), "resaved"));
  }
  // For the record: most bytes are cell statistics, where other values are often valid.
  std::printf("%zu of %zu single-byte changes load\n", accepted, original.size() - 16);
  // Trailing garbage.
  b = original;
  b.insert(b.end() - 4, {1, 2, 3});
  expectRejected(b, "trailing bytes");
}

TEST(MapIo, UnreadableFilesGiveClearErrors) {
  EXPECT_THROW(ndtom::loadMap("/nonexistent/dir/map.ndtom"), std::runtime_error);
  const std::string path = tempPath("garbage");
  std::ofstream(path) << "this is not a map";
  try {
    ndtom::loadMap(path);
    FAIL() << "garbage loaded";
  } catch (const ndtom::MapFormatError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << "message names the file";
  }
  std::remove(path.c_str());
}

TEST(MapIo, SaveReplacesAtomicallyAndLeavesNoTemporary) {
  const std::string path = tempPath("atomic");
  ndtom::saveMap(sampleMap(), path);
  ndtom::saveMap(NdtMap(), path);
  EXPECT_TRUE(ndtom::loadMap(path).isEmpty());
  EXPECT_FALSE(std::filesystem::exists(ndtom::temporaryPathFor(path)));
  EXPECT_THROW(ndtom::saveMap(NdtMap(), "/nonexistent/dir/map.ndtom"), std::runtime_error);
  std::remove(path.c_str());
}

// A count is checked against the bytes left before anything is allocated for it. A 237-byte
// file whose count overlapped the checksum made `remaining() - 4` underflow: the loader then
// reserved room for the count (922 MB) before failing, and counts of 1.7e9 and more gave
// std::bad_alloc instead of a format error. Here the block count (format 2), whose high half
// is the checksum of what precedes it.
TEST(MapIo, CountOverlappingTheChecksumIsCheckedAgainstTheBytesLeft) {
  const auto empty = ndtom::encodeMap(NdtMap());  // options, u64 0, u64 0, u8 coding, CRC
  const std::vector<uint8_t> head(empty.begin(), empty.end() - 13);
  for (const uint32_t low : {0u, 1u, 5000u, 0xFFFFFFFFu}) {
    std::vector<uint8_t> file = head;
    for (int i = 0; i < 4; ++i) file.push_back(uint8_t(low >> (8 * i)));
    const uint32_t crc = ndtom::crc32(file.data(), file.size());
    for (int i = 0; i < 4; ++i) file.push_back(uint8_t(crc >> (8 * i)));
    try {
      ndtom::decodeMap(file.data(), file.size(), "overlap");
      FAIL() << "loaded";
    } catch (const ndtom::MapFormatError& e) {
      EXPECT_NE(std::string(e.what()).find("exceeds the file size"), std::string::npos) << e.what();
    }
  }
}

// The encoding streamed in pieces is encodeMap()'s bytes, and encodedMapSize() their number.
TEST(MapIo, StreamedEncodingIsTheSameBytes) {
  NdtMap map;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-30, 30);
  std::vector<Vector3d> pts;
  for (int i = 0; i < 60000; ++i) pts.emplace_back(u(rng), u(rng), u(rng) / 10);
  map.insertScan(pts, Vector3d(0, 0, 0));
  const auto whole = ndtom::encodeMap(map);
  ASSERT_GT(whole.size(), size_t(5) << 19);  // several pieces
  std::vector<uint8_t> streamed;
  size_t pieces = 0;
  ndtom::encodeMap(map, [&](const uint8_t* data, size_t size) {
    streamed.insert(streamed.end(), data, data + size);
    ++pieces;
  });
  EXPECT_EQ(streamed, whole);
  EXPECT_GT(pieces, 2u);
  EXPECT_EQ(ndtom::encodedMapSize(map), whole.size());
}

// Loading stays within a memory budget: a small file of cells far apart (a block each) is
// refused before its blocks take more, and so is a file larger than the budget.
TEST(MapIo, LoadingRespectsTheMemoryBudget) {
  NdtMap sparse;
  for (int i = 0; i < 3000; ++i) sparse.setCell({16 * i, 0, 0}, 1.f, {});
  const auto bytes = ndtom::encodeMap(sparse);  // 42 kB for 3000 blocks of 2 kB
  try {
    ndtom::decodeMap(bytes.data(), bytes.size(), "sparse.ndtom", 2000000);
    FAIL() << "loaded within 2 MB";
  } catch (const ndtom::MemoryBudgetError& e) {
    EXPECT_NE(std::string(e.what()).find("sparse.ndtom: loading 3000 cells"), std::string::npos)
        << e.what();
    EXPECT_LE(e.budget(), 2000000u);
  }
  EXPECT_EQ(ndtom::decodeMap(bytes.data(), bytes.size(), "sparse.ndtom", 20000000).numCells(),
            3000u);
  const std::string path = tempPath("budget");
  ndtom::saveMap(sparse, path);
  EXPECT_THROW(ndtom::loadMap(path, bytes.size() - 1), ndtom::MemoryBudgetError);
  EXPECT_EQ(ndtom::loadMap(path, 20000000).numCells(), 3000u);
  std::remove(path.c_str());
}
