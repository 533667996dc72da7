// The out-of-core build's spill files (src/spill_codec.h): a round trip gives the map back bit
// for bit, with the memory accounting the map format's loader gives; a damaged or cut file is
// refused with MapFormatError, never read into a wrong map or a crash.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>

#include "ndtom/files/map_io.h"
#include "ndtom_internal/crc32.h"
#include "scale/spill_codec.h"
#include "support/map_equality.h"

namespace {

using ndtom::MapFormatError;
using ndtom::NdtMap;
using ndtom::SpillCodec;
using Eigen::Vector3d;

NdtMap scannedMap(double resolution, int scans, int points) {
  ndtom::MapOptions o;
  o.resolution = resolution;
  o.scan.max_range = 8.0;
  NdtMap map(o);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-4, 4);
  for (int s = 0; s < scans; ++s) {
    std::vector<Vector3d> pts;
    for (int i = 0; i < points; ++i) pts.emplace_back(u(rng), u(rng), i % 3 ? -1.0 : u(rng));
    map.insertScan(pts, Vector3d(0.2 * s, 0.1, 0.5));
  }
  return map;
}

std::string spill(const NdtMap& map) {
  std::string bytes;
  SpillCodec::write(map, [&](const uint8_t* d, size_t n) { bytes.append(reinterpret_cast<const char*>(d), n); });
  return bytes;
}

TEST(SpillCodec, RoundTripIsTheMapBitForBit) {
  const NdtMap map = scannedMap(0.3, 5, 400);
  ASSERT_GT(map.numGaussians(), 20u);
  const NdtMap back = SpillCodec::read(spill(map), map.options(), "test");
  ndtom::testing::expectBitIdentical(map, back);
  EXPECT_EQ(ndtom::encodeMap(back), ndtom::encodeMap(map));
  // What the map format's loader gives: no spare statistics room, the same bytes counted.
  const std::vector<uint8_t> file = ndtom::encodeMap(map);
  EXPECT_EQ(back.memoryBytes(), ndtom::decodeMap(file.data(), file.size()).memoryBytes());
  EXPECT_EQ(back.numGaussians(), map.numGaussians());
}

TEST(SpillCodec, AnEmptyMapRoundTrips) {
  const NdtMap empty;
  EXPECT_TRUE(SpillCodec::read(spill(empty), empty.options(), "test").isEmpty());
}

TEST(SpillCodec, EveryCutAndEveryFlippedByteIsRefused) {
  const NdtMap map = scannedMap(0.9, 1, 12);
  const std::string bytes = spill(map);
  ASSERT_LT(bytes.size(), 40000u);
  for (size_t n = 0; n < bytes.size(); ++n)
    EXPECT_THROW(SpillCodec::read(bytes.substr(0, n), map.options(), "cut"), MapFormatError)
        << n << " bytes";
  for (size_t i = 0; i < bytes.size(); ++i) {
    std::string damaged = bytes;
    damaged[i] = char(damaged[i] ^ 0x10);
    EXPECT_THROW(SpillCodec::read(damaged, map.options(), "flipped"), MapFormatError)
        << "byte " << i;
  }
}

// Damage that keeps the checksum valid (it is recomputed): the counts and masks are checked
// against the file on their own.
TEST(SpillCodec, StructureIsCheckedBehindTheChecksum) {
  NdtMap map;
  const ndtom::CellStats stats = ndtom::CellStats::fromPoints(
      {Vector3d(0.01, 0, 0.02), {-0.01, 0.02, 0}, {0, -0.02, 0.01}});
  map.setCell({1, 2, 3}, 1.5f, stats);  // block (0, 0, 0): its first known cell has statistics
  for (int32_t x = 20; x < 24; ++x) map.setCell({x, 2, 3}, -0.5f, {});  // block (2, 0, 0)
  const std::string bytes = spill(map);
  ASSERT_NO_THROW(SpillCodec::read(bytes, map.options(), "intact"));
  auto resealed = [](std::string b) {
    const uint32_t crc = ndtom::crc32(b.data(), b.size() - 4);
    std::memcpy(&b[b.size() - 4], &crc, 4);
    return b;
  };
  auto putU64 = [](std::string& b, size_t at, uint64_t v) { std::memcpy(&b[at], &v, 8); };
  // Offsets: magic 8, block count 8; per block: index 12, known mask 64, log-odds 4 per known
  // cell, statistics mask 64, statistics count 4, 100 bytes per statistics.
  const size_t count_at = 8, first_block = 16;
  int64_t stats_block = -1;  // which of the two blocks comes first is the hash table's order
  size_t stats_block_size = 0;
  for (size_t b = 0, at = first_block; b < 2; ++b) {
    ndtom::CellIndex index;
    std::memcpy(&index, &bytes[at], sizeof index);
    const size_t size = 12 + 64 + 4 * (index.x == 0 ? 1 : 4) + 64 + 4 + (index.x == 0 ? 100 : 0);
    if (index.x == 0) stats_block = int64_t(at), stats_block_size = size;
    at += size;
  }
  ASSERT_GE(stats_block, 0);
  const size_t stats_count_at = size_t(stats_block) + 12 + 64 + 4 + 64;

  struct Case {
    std::string what, bytes, message;
  };
  std::vector<Case> cases;
  std::string b = bytes;
  putU64(b, count_at, uint64_t(1) << 40);
  cases.push_back({"block count beyond the file", b, "block count exceeds the file"});
  b = bytes;
  putU64(b, count_at, 1);
  cases.push_back({"bytes after the last block", b, "bytes after the last block"});
  b = bytes;
  putU64(b, count_at, 3);
  cases.push_back({"a block missing", b, "block count exceeds the file"});
  b = bytes;
  b[stats_count_at] = 2;
  cases.push_back({"statistics count above its mask", b, "statistics count does not match its mask"});
  b = bytes;
  b[stats_count_at] = 0;
  cases.push_back({"statistics count below its mask", b, "statistics count does not match its mask"});
  const size_t stats_mask_at = size_t(stats_block) + 12 + 64 + 4;
  b = bytes;
  std::memset(&b[stats_mask_at], 0, 64);
  b[stats_mask_at] = 1;  // the statistics moved to cell 0, which is unknown
  cases.push_back({"statistics in an unknown cell", b, "statistics in an unknown cell"});
  b = bytes;  // the block rewritten with no known cell and no statistics
  b.replace(size_t(stats_block) + 12, 64 + 4 + 64 + 4 + 100, std::string(64 + 64 + 4, '\0'));
  cases.push_back({"a block without known cells", b, "an empty block"});
  b = bytes.substr(0, bytes.size() - 4);  // the first block again, then a seal
  const size_t first_size = size_t(stats_block) == first_block ? stats_block_size
                                                                 : 12 + 64 + 16 + 64 + 4;
  b += bytes.substr(first_block, first_size) + "SEAL";
  putU64(b, count_at, 3);
  cases.push_back({"a block twice", b, "a block twice"});
  std::memcpy(&b[0], "NDTOMMAP", 8);
  cases.push_back({"not a spill file", b, "not a spill file"});
  for (const Case& c : cases) {
    try {
      SpillCodec::read(resealed(c.bytes), map.options(), c.what);
      ADD_FAILURE() << c.what << ": read";
    } catch (const MapFormatError& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << c.what << ": " << e.what();
    }
  }
}

}  // namespace
