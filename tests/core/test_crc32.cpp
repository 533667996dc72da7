// ndtom::crc32 (slicing by 8) against zlib's crc32, an independent implementation of the same
// CRC-32/IEEE, on every length and alignment that exercises the 8-byte loop and its tail.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <random>
#include <vector>

#include "ndtom_internal/crc32.h"

namespace {

std::vector<uint8_t> randomBytes(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> b(n);
  for (uint8_t& x : b) x = uint8_t(rng());
  return b;
}

uint32_t zlibCrc(const uint8_t* data, size_t n) {
  return uint32_t(::crc32(::crc32(0L, Z_NULL, 0), data, uInt(n)));
}

}  // namespace

TEST(Crc32, MatchesTheStandardCheckValue) {
  EXPECT_EQ(ndtom::crc32("123456789", 9), 0xCBF43926u);  // the published CRC-32/IEEE value
  EXPECT_EQ(ndtom::crc32("", 0), 0u);
}

TEST(Crc32, MatchesZlibAtEveryLengthAndAlignment) {
  const std::vector<uint8_t> bytes = randomBytes(300, 1);
  for (size_t offset = 0; offset < 8; ++offset)
    for (size_t n = 0; offset + n <= bytes.size(); ++n)
      ASSERT_EQ(ndtom::crc32(bytes.data() + offset, n), zlibCrc(bytes.data() + offset, n))
          << "offset " << offset << ", " << n << " bytes";
}

TEST(Crc32, ContinuedOverPiecesEqualsOneCall) {
  const std::vector<uint8_t> bytes = randomBytes(1 << 20, 2);
  const uint32_t whole = zlibCrc(bytes.data(), bytes.size());
  EXPECT_EQ(ndtom::crc32(bytes.data(), bytes.size()), whole);
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    uint32_t crc = 0;
    for (size_t at = 0; at < bytes.size();) {
      const size_t n = std::min(bytes.size() - at, size_t(rng() % 5000));
      crc = ndtom::crc32(bytes.data() + at, n, crc);
      at += n;
    }
    ASSERT_EQ(crc, whole) << "trial " << trial;
  }
}

TEST(Crc32, EveryFlippedBitChangesIt) {
  std::vector<uint8_t> bytes = randomBytes(64, 4);
  const uint32_t clean = ndtom::crc32(bytes.data(), bytes.size());
  for (size_t i = 0; i < bytes.size(); ++i)
    for (int bit = 0; bit < 8; ++bit) {
      bytes[i] ^= uint8_t(1 << bit);
      EXPECT_NE(ndtom::crc32(bytes.data(), bytes.size()), clean) << "byte " << i << " bit " << bit;
      bytes[i] ^= uint8_t(1 << bit);
    }
}
