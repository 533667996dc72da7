// PCD reading: every data encoding, any field list, and clear errors for broken files.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "ndtom_io/pcd_reader.h"

using ndtom::io::parsePcd;
using ndtom::io::PcdError;

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

// A valid LZF stream made of literal runs only (control byte = run length − 1 < 32).
std::string lzfLiterals(const std::string& raw) {
  std::string out;
  for (size_t i = 0; i < raw.size(); i += 32) {
    const size_t run = std::min<size_t>(32, raw.size() - i);
    out.push_back(char(run - 1));
    out.append(raw, i, run);
  }
  return out;
}

void expectError(const std::string& bytes, const std::string& fragment) {
  try {
    parsePcd(bytes, "test.pcd");
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
  expectError(header("x y z", "4 4 4", "F F F", 1000000000, "binary"), "truncated");
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
