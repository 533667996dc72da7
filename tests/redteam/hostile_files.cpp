#include "hostile_files.h"

#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>
#include <zlib.h>

#include <algorithm>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom/files/map_io.h"
#include "ndtom_internal/crc32.h"

namespace redteam {

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

void writeFile(const std::string& path, const std::vector<uint8_t>& bytes) {
  writeFile(path, std::string(bytes.begin(), bytes.end()));
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string pcdHeader(uint64_t points, const std::string& data) {
  return "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " +
         std::to_string(points) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
         std::to_string(points) + "\nDATA " + data + "\n";
}

std::string pcdBinaryPoints(const std::vector<Eigen::Vector3d>& points) {
  std::string out;
  for (const auto& p : points) {
    const float v[3] = {float(p.x()), float(p.y()), float(p.z())};
    out.append(reinterpret_cast<const char*>(v), sizeof(v));
  }
  return out;
}

namespace {

void pngChunk(std::ofstream& out, const char* type, const std::string& data) {
  const uint32_t n = uint32_t(data.size());
  const char len[4] = {char(n >> 24), char(n >> 16), char(n >> 8), char(n)};
  out.write(len, 4);
  std::string body = std::string(type, 4) + data;
  out.write(body.data(), std::streamsize(body.size()));
  const uint32_t crc = ndtom::crc32(body.data(), body.size());
  const char c[4] = {char(crc >> 24), char(crc >> 16), char(crc >> 8), char(crc)};
  out.write(c, 4);
}

}  // namespace

void writeFlatPng(const std::string& path, uint32_t width, uint32_t height, uint16_t value) {
  std::ofstream out(path, std::ios::binary);
  out.write("\x89PNG\r\n\x1a\n", 8);
  std::string ihdr;
  for (const uint32_t v : {width, height})
    for (int s = 24; s >= 0; s -= 8) ihdr.push_back(char(v >> s));
  ihdr += std::string("\x10\x00\x00\x00\x00", 5);  // 16-bit, grey, deflate, no filter/interlace
  pngChunk(out, "IHDR", ihdr);
  std::string row(1 + 2 * size_t(width), '\0');  // filter byte 0, big-endian samples
  for (size_t i = 0; i < width; ++i)
    row[1 + 2 * i] = char(value >> 8), row[2 + 2 * i] = char(value);
  z_stream z{};
  deflateInit(&z, 9);
  std::string compressed(1 << 20, '\0');
  for (uint32_t y = 0; y <= height; ++y) {
    const bool last = y == height;
    z.next_in = reinterpret_cast<Bytef*>(last ? nullptr : row.data());
    z.avail_in = last ? 0 : uInt(row.size());
    do {
      z.next_out = reinterpret_cast<Bytef*>(compressed.data());
      z.avail_out = uInt(compressed.size());
      deflate(&z, last ? Z_FINISH : Z_NO_FLUSH);
      const size_t have = compressed.size() - z.avail_out;
      if (have > 0) pngChunk(out, "IDAT", compressed.substr(0, have));
    } while (z.avail_out == 0);
  }
  deflateEnd(&z);
  pngChunk(out, "IEND", "");
}

std::vector<Eigen::Vector3d> pointsAround(const Eigen::Vector3d& centre, double range, int n,
                                          unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i)
    points.push_back(centre + range * Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized());
  return points;
}

std::string kittiPoses(const std::vector<Eigen::Vector3d>& positions) {
  std::ostringstream s;
  s.precision(17);
  for (const auto& p : positions)
    s << "1 0 0 " << p.x() << " 0 1 0 " << p.y() << " 0 0 1 " << p.z() << "\n";
  return s.str();
}

void writeLaserRawlog(const std::string& path, int scans, float range) {
  mrpt::io::CFileOutputStream file(path);  // plain: damaged bytes reach the reader as they are
  auto archive = mrpt::serialization::archiveFrom(file);
  for (int k = 0; k < scans; ++k) {
    mrpt::obs::CObservationOdometry odometry;
    odometry.odometry = mrpt::poses::CPose2D(k, 0, 0);
    odometry.timestamp = mrpt::Clock::fromDouble(1000.0 + k);
    mrpt::obs::CObservation2DRangeScan scan;
    scan.aperture = float(M_PI);
    scan.maxRange = std::max(range * 1.5f, 80.f);
    scan.resizeScan(361);
    for (size_t i = 0; i < 361; ++i) {
      scan.setScanRange(i, range);
      scan.setScanRangeValidity(i, true);
    }
    scan.timestamp = mrpt::Clock::fromDouble(1000.1 + k);
    archive << odometry << scan;
  }
}

std::vector<uint8_t> ndtommapBytes(size_t* map_size_at) {
  mrpt_ndtom::CNDTOccupancyMap map(0.5);
  map.insertPoints(pointsAround({0, 0, 0}, 3, 200, 1), {0.1, 0.1, 0.1});
  mrpt::io::CMemoryStream buffer;
  mrpt::serialization::archiveFrom(buffer) << map;
  const auto* raw = static_cast<const uint8_t*>(buffer.getRawBufferData());
  std::vector<uint8_t> bytes(raw, raw + buffer.getTotalBytesCount());
  // The map data ends the object, before MRPT's end flag (1 byte): its size precedes it.
  const auto encoded = ndtom::encodeMap(map.ndtMap());
  const size_t data_at = size_t(
      std::search(bytes.begin(), bytes.end(), encoded.begin(), encoded.end()) - bytes.begin());
  if (data_at >= bytes.size()) throw std::logic_error("map data not found in the archive");
  *map_size_at = data_at - 8;
  return bytes;
}

}  // namespace redteam
