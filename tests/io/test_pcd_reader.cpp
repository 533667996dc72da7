// PCD reading: every data encoding, any field list, and clear errors for broken files.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "ndtom_io/pcd_reader.h"
#include "support/pcd_bytes.h"
#include "support/special_files.h"

using ndtom::io::parsePcd;
using ndtom::io::PcdError;
using ndtom::testing::lzfLiterals;

namespace {

std::string header(const std::string& fields, const std::string& size, const std::string& type,
                   size_t n, const std::string& data) {
  return "VERSION 0.7\nFIELDS " + fields + "\nSIZE " + size + "\nTYPE " + type + "\nWIDTH " +
         std::to_string(n) + "\nHEIGHT 1\nPOINTS " + std::to_string(n) + "\nDATA " + data + "\n";
}

template <class T>
void append(std::string& s, T v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof(v));
}

void expectError(const std::string& bytes, const std::string& fragment,
                 uint64_t max_points = ndtom::io::kDefaultMaxPcdPoints) {
  try {
    parsePcd(bytes, "test.pcd", max_points);
    FAIL() << "accepted; expected an error containing '" << fragment << "'";
  } catch (const PcdError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("test.pcd"), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(PcdReader, AsciiWithExtraFieldsInAnyOrder) {
  const std::string text =
      "# comment\nVERSION .7\nFIELDS intensity z rgb x y\nSIZE 4 4 4 4 4\n"
      "TYPE F F U F F\nCOUNT 1 1 1 1 1\nWIDTH 2\nHEIGHT 1\n"
      "VIEWPOINT 1 2 3 1 0 0 0\nPOINTS 2\nDATA ascii\n"
      "0.5 3 255 1 2\n9 -6 0 -4 -5\n";
  const auto cloud = parsePcd(text, "a.pcd");
  ASSERT_EQ(cloud.points.size(), 2u);
  EXPECT_EQ(cloud.points[0], Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(cloud.points[1], Eigen::Vector3d(-4, -5, -6));
  EXPECT_EQ(cloud.viewpoint.translation(), Eigen::Vector3d(1, 2, 3));
}

TEST(PcdReader, BinaryMixedTypes) {
  std::string bytes = header("x y z ring", "8 4 2 1", "F F I U", 2, "binary");
  append(bytes, 1.25);
  append(bytes, 2.5f);
  append(bytes, int16_t(-7));
  append(bytes, uint8_t(3));
  append(bytes, -1.0);
  append(bytes, 0.0f);
  append(bytes, int16_t(300));
  append(bytes, uint8_t(4));
  const auto cloud = parsePcd(bytes, "b.pcd");
  ASSERT_EQ(cloud.points.size(), 2u);
  EXPECT_EQ(cloud.points[0], Eigen::Vector3d(1.25, 2.5, -7));
  EXPECT_EQ(cloud.points[1], Eigen::Vector3d(-1, 0, 300));
}

TEST(PcdReader, BinaryCompressedStoresFieldsAsColumns) {
  const float xs[3] = {1, 2, 3}, ys[3] = {4, 5, 6}, zs[3] = {7, 8, 9}, is[3] = {0, 0, 0};
  std::string raw;
  for (const float* column : {is, xs, ys, zs})
    raw.append(reinterpret_cast<const char*>(column), sizeof(float) * 3);
  const std::string packed = lzfLiterals(raw);
  std::string bytes = header("intensity x y z", "4 4 4 4", "F F F F", 3, "binary_compressed");
  append(bytes, uint32_t(packed.size()));
  append(bytes, uint32_t(raw.size()));
  bytes += packed;
  const auto cloud = parsePcd(bytes, "c.pcd");
  ASSERT_EQ(cloud.points.size(), 3u);
  EXPECT_EQ(cloud.points[2], Eigen::Vector3d(3, 6, 9));

  // The same data with a back-reference: 12 zero bytes written as 1 literal + a copy of 11.
  std::string with_ref;
  with_ref.push_back(0);             // literal run of 1
  with_ref.push_back(0);             // the zero
  with_ref.push_back(char(7 << 5));  // length 7 + extension byte, offset high bits 0
  with_ref.push_back(char(11 - 2 - 7));
  with_ref.push_back(0);  // offset 1 back
  with_ref += lzfLiterals(raw.substr(12));
  std::string bytes2 = header("intensity x y z", "4 4 4 4", "F F F F", 3, "binary_compressed");
  append(bytes2, uint32_t(with_ref.size()));
  append(bytes2, uint32_t(raw.size()));
  bytes2 += with_ref;
  EXPECT_EQ(parsePcd(bytes2, "c2.pcd").points, cloud.points);
}

TEST(PcdReader, RealLidarScanMatchesItsRawBytes) {
  const std::string path = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld/full3.pcd";
  const auto cloud = ndtom::io::readPcd(path);
  std::ifstream f(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const size_t data = bytes.find("DATA binary\n") + 12;
  ASSERT_EQ((bytes.size() - data) / 16, cloud.points.size());
  ASSERT_GT(cloud.points.size(), 30000u);
  for (size_t i = 0; i < cloud.points.size(); i += 997) {
    float v[4];
    std::memcpy(v, bytes.data() + data + 16 * i, 16);
    EXPECT_EQ(cloud.points[i], Eigen::Vector3d(v[0], v[1], v[2]));
  }
}

TEST(PcdReader, BrokenFilesGiveClearErrors) {
  expectError("", "no DATA");
  expectError(header("x y", "4 4", "F F", 1, "ascii") + "1 2\n", "missing field 'z'");
  expectError(header("x y z", "4 4 4", "F F F", 3, "ascii") + "1 2 3\n", "truncated");
  expectError(header("x y z", "4 4 4", "F F F", 2, "ascii") + "1 2\n3 4 5\n", "values");
  expectError(header("x y z", "4 4 4", "F F F", 1, "ascii") + "1 a 3\n", "bad number");
  expectError(header("x y z", "4 4 4", "F F F", 5, "binary") + std::string(40, '\0'), "truncated");
  expectError(header("x y z", "4 4 4", "F F F", 10000000, "binary"), "truncated");
  expectError(header("x y z", "4 4", "F F F", 1, "binary"), "different lengths");
  expectError(header("x y z", "3 4 4", "F F F", 1, "binary"), "unsupported type");
  expectError(header("x y z", "4 4 4", "F F F", 1, "lzma"), "unknown DATA");
  std::string c = header("x y z", "4 4 4", "F F F", 1, "binary_compressed");
  append(c, uint32_t(4));
  append(c, uint32_t(12));
  expectError(c + std::string(4, '\x1f'), "compressed");
  EXPECT_THROW(ndtom::io::readPcd("/nonexistent.pcd"), PcdError);
}

TEST(PcdReader, WriteThenReadRoundTrip) {
  const std::string path = ::testing::TempDir() + "/roundtrip.pcd";
  const std::vector<Eigen::Vector3d> pts = {{1, 2, 3}, {-0.5, 0.25, 8}};
  ndtom::io::writePcdBinary(path, pts);
  EXPECT_EQ(ndtom::io::readPcd(path).points, pts);
}

// Sizes from the header are checked, never wrapped or truncated. Before, the first file below
// (131,072 fields of 2^20 doubles and 2^24 points: 2^40 bytes a point, 2^64 in all, which
// wrapped to 0) passed the size check and the reader read past an empty buffer; COUNT
// 4294967297 was read as 1 and SIZE 4294967300 as 4.
TEST(PcdReader, HeaderSizesAreCheckedNotWrapped) {
  expectError(ndtom::testing::wrappingCompressedPcd(), "131072 FIELDS");

  // Within the field limits, 2^40 points of 2^24 bytes: the product wraps to 0.
  expectError(ndtom::testing::wideWrappingCompressedPcd(), "does not match the fields and POINTS",
              UINT64_MAX);

  const std::string tail = "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n";
  expectError("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 4294967297 1 1\n" + tail,
              "bad COUNT '4294967297'");
  expectError("FIELDS x y z\nSIZE 4294967300 4 4\nTYPE F F F\n" + tail, "bad SIZE '4294967300'");
  expectError("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT -1 1 1\n" + tail, "bad COUNT '-1'");
  expectError(
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4294967296\nHEIGHT 4294967296\n"
      "POINTS 0\nDATA ascii\n",
      "WIDTH x HEIGHT");
  expectError(header("x y z", "4 4 4", "F F F", 1000, "binary"), "1000 points, more than the 999",
              999);
  expectError(
      header("x y z", "4 4 4", "F F F", 1, "ascii").replace(0, 0, "VIEWPOINT nan 0 0 1 0 0 0\n") +
          "1 2 3\n",
      "bad VIEWPOINT 'nan'");
}

// A FIFO named scan.pcd made the reader wait for a writer forever; /dev/zero read 2 GB.
TEST(PcdReader, RefusesFilesThatAreNotRegularFiles) {
  const ndtom::testing::Fifo fifo(::testing::TempDir() + "/scan.pcd");
  auto message = [](const std::string& path) {
    try {
      ndtom::io::readPcd(path);
    } catch (const PcdError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(fifo.path()).find(fifo.path() + ": a FIFO"), std::string::npos)
      << message(fifo.path());
  EXPECT_NE(message(ndtom::testing::kEndlessFile).find("/dev/zero: a device"), std::string::npos)
      << message(ndtom::testing::kEndlessFile);
  EXPECT_NE(message(::testing::TempDir()).find("a folder"), std::string::npos);
}
