// Writes the seed corpus of fuzz_mrpt_deserialization: small CNDTOccupancyMap archives made
// from the real lidar scans in tests/data (a few metres around the sensor, coarse cells, so
// that each seed stays a few KB), and damaged variants of one of them. Not part of the
// normal build: cmake --build <dir> --target make_mrpt_seeds && <dir>/tests/fuzz/make_mrpt_seeds
// tests/data/balm-realworld tests/fuzz/corpus/fuzz_mrpt_deserialization
// The corpus's v0_* seeds were written by an earlier version (insertion options without
// threads), its likelihood_v0_* seeds by another (likelihood options without the method),
// its format1_* seeds by serialization version 0 (the map in file format 1); this program
// does not rewrite them.
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom/files/map_io.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

using Eigen::Vector3d;
using mrpt_ndtom::CNDTOccupancyMap;

namespace {

std::vector<uint8_t> serialize(const CNDTOccupancyMap& map) {
  mrpt::io::CMemoryStream buffer;
  mrpt::serialization::archiveFrom(buffer) << map;
  const auto* raw = static_cast<const uint8_t*>(buffer.getRawBufferData());
  return {raw, raw + buffer.getTotalBytesCount()};
}

void write(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  std::printf("%s: %zu bytes\n", path.c_str(), bytes.size());
}

// Scan `index` in the world frame, only points within `radius` (m) of the sensor, every
// `step`-th of them.
struct Scan {
  std::vector<Vector3d> points;
  Vector3d origin;
};
Scan croppedScan(const std::string& folder, int index, double radius, size_t step) {
  const auto cloud = ndtom::io::readPcd(folder + "/full" + std::to_string(index) + ".pcd");
  const auto pose = ndtom::io::readPoseFile(folder + "/poses.txt").at(size_t(index)).pose;
  Scan scan{{}, pose.translation()};
  size_t kept = 0;
  for (const Vector3d& p : cloud.points)
    if (p.allFinite() && p.norm() < radius && kept++ % step == 0) scan.points.push_back(pose * p);
  return scan;
}

size_t find(const std::vector<uint8_t>& haystack, const std::vector<uint8_t>& needle) {
  return size_t(std::search(haystack.begin(), haystack.end(), needle.begin(), needle.end()) -
                haystack.begin());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: make_mrpt_seeds BALM_FOLDER OUT_FOLDER\n");
    return 2;
  }
  const std::string data = argv[1], out = std::string(argv[2]) + "/";

  // Occupancy on, two scans: occupied Gaussians, free cells, cells that lost their Gaussian.
  CNDTOccupancyMap occupancy(2.0);
  for (int i = 0; i < 2; ++i) {
    const Scan s = croppedScan(data, i, 5.0, 40);
    occupancy.insertPoints(s.points, s.origin);
  }
  const std::vector<uint8_t> good = serialize(occupancy);
  write(out + "lidar_occupancy", good);

  // Recursive NDT (no rays), other ray mode and threads, non-default likelihood and render
  // options.
  CNDTOccupancyMap recursive(1.5);
  recursive.insertionOptions.occupancy.enabled = false;
  recursive.insertionOptions.scan.ray_mode = ndtom::RayMode::PerHitCell;
  recursive.insertionOptions.scan.threads = 2;
  recursive.likelihoodOptions.search_neighbours = false;
  recursive.likelihoodOptions.decimation = 3;
  recursive.likelihoodOptions.likelihood_method = CNDTOccupancyMap::TLikelihoodMethod::NdtMcl;
  recursive.likelihoodOptions.ndt_mcl_scan_factor = 2;
  recursive.likelihoodOptions.ndt_mcl_map_factor = 2;
  recursive.likelihoodOptions.ndt_mcl_max_gaussians = 120;
  recursive.renderOptions.show_free_cells = true;
  recursive.renderOptions.colormap = mrpt::img::cmHOT;
  recursive.genericMapParams.enableSaveAs3DObject = false;
  const Scan s = croppedScan(data, 5, 3.0, 30);
  recursive.insertPoints(s.points, s.origin);
  write(out + "lidar_recursive", serialize(recursive));

  CNDTOccupancyMap empty(0.25);
  empty.insertionOptions.scan.max_range = 30.0;
  write(out + "empty", serialize(empty));

  // Damaged copies of the first: each must be rejected with an exception.
  const std::vector<uint8_t> map_bytes = ndtom::encodeMap(occupancy.ndtMap());
  const size_t map_at = find(good, map_bytes);
  const size_t size_at = map_at - 8;  // the uint64 byte count before the map data
  auto damaged = good;
  damaged.resize(map_at + map_bytes.size() / 2);
  write(out + "damaged_truncated", damaged);
  damaged = good;
  std::memset(damaged.data() + size_at, 0xff, 8);
  write(out + "damaged_huge_size", damaged);
  damaged = good;
  damaged[map_at + map_bytes.size() / 3] ^= 0x40;
  write(out + "damaged_checksum", damaged);

  mrpt::io::CMemoryStream options;
  auto archive = mrpt::serialization::archiveFrom(options);
  occupancy.insertionOptions.writeToStream(archive);
  const auto* raw = static_cast<const uint8_t*>(options.getRawBufferData());
  const size_t options_at = find(good, {raw, raw + options.getTotalBytesCount()});
  damaged = good;
  damaged[options_at + 1 + 8] = 7;  // after the version byte and the resolution: a bool
  write(out + "damaged_bool", damaged);
  damaged = good;
  damaged[options_at + 1 + 8 + 1 + 7] ^= 0x7f;  // p_hit's sign and exponent: 0.6 -> ~4e4
  write(out + "damaged_p_hit", damaged);
  damaged = good;
  std::memset(damaged.data() + options_at + 86, 0, 4);  // threads, the last field: 1 -> 0
  write(out + "damaged_threads", damaged);
  // The likelihood options follow the insertion options (90 bytes): version byte, 41 bytes of
  // version 0 fields, then the method.
  damaged = good;
  damaged[options_at + 90 + 42] = 9;  // no such method
  write(out + "damaged_likelihood_method", damaged);
  return 0;
}
