// The out-of-core build's spill files (src/spill_codec.h): a round trip gives the map back bit
// for bit, with the memory accounting the map format's loader gives; a damaged or cut file is
// refused with MapFormatError, never read into a wrong map or a crash.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "ndtom/map_io.h"
#include "spill_codec.h"
#include "support/map_equality.h"

namespace {

using ndtom::MapFormatError;
using ndtom::NdtMap;
using ndtom::SpillCodec;
using Eigen::Vector3d;

NdtMap scannedMap(double resolution, int scans, int points) {
  ndtom::MapOptions o;
  o.resolution = resolution;
  o.insertion.max_range = 8.0;
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

}  // namespace
