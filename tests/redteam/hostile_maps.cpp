#include "hostile_maps.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "mrpt_ndtom/encoded_archive.h"
#include "ndtom/files/map_io.h"
#include "ndtom/files/tiled_map_io.h"
#include "ndtom/map/block_grid.h"
#include "ndtom_internal/crc32.h"

namespace redteam {
namespace {

constexpr uint64_t kWriterBudget = uint64_t(8) << 30;  // the writer's maps are not the test

// One occupied Gaussian per block, `blocks` of them around the origin: `cube`, in adjacent
// blocks of a cube; else on a square grid of the z = 0 layer 16 blocks apart, so that each
// stays alone in its block at every level of a registration pyramid of factors up to 16.
ndtom::NdtMap sparseMap(ndtom::MapOptions options, size_t blocks, bool cube) {
  options.scan.memory_budget = kWriterBudget;
  ndtom::NdtMap map(options);
  const int side = int(std::ceil(cube ? std::cbrt(double(blocks)) : std::sqrt(double(blocks))));
  const int spacing = (cube ? 1 : 16) * ndtom::kBlockEdge;  // cells
  const int layers = cube ? side : 1;
  ndtom::CellStats stats;
  stats.n = 10;
  stats.scatter = Eigen::Matrix3d::Identity() * 0.01 * 9;
  size_t made = 0;
  for (int z = 0; z < layers && made < blocks; ++z)
    for (int y = 0; y < side && made < blocks; ++y)
      for (int x = 0; x < side && made < blocks; ++x, ++made) {
        const ndtom::CellIndex cell{(x - side / 2) * spacing + 3, (y - side / 2) * spacing + 3,
                                    (z - layers / 2) * spacing + 3};
        if (!map.setCell(cell, 2.f, stats)) throw std::runtime_error("setCell refused a cell");
      }
  return map;
}

void writeNdtommap(const ndtom::NdtMap& map, const mrpt_ndtom::CNDTOccupancyMap& shell,
                   const std::string& path) {
  mrpt::io::CFileGZOutputStream file(path);
  auto archive = mrpt::serialization::archiveFrom(file);
  mrpt_ndtom::writeWithEncodedMap(archive, shell, ndtom::encodeMap(map));
}

int run(const std::vector<std::string>& a) {
  if (a.size() >= 5 && a[0] == "sparse") {
    const std::string& format = a[1];
    const bool cube = a[2] == "cube";
    const size_t blocks = std::stoul(a[3]);
    const std::string& path = a[4];
    mrpt_ndtom::CNDTOccupancyMap shell(0.2);
    const ndtom::NdtMap map = sparseMap(shell.insertionOptions.toMapOptions(), blocks, cube);
    if (format == "ndtom")
      ndtom::saveMap(map, path);
    else if (format == "ndtommap")
      writeNdtommap(map, shell, path);
    else if (format == "tiles" && a.size() == 6)
      ndtom::saveTiledMap(map, path, std::stoi(a[5]));
    else
      throw std::invalid_argument("sparse: unknown format " + format);
    std::printf("wrote %s: %zu blocks\n", path.c_str(), map.numBlocks());
    return 0;
  }
  if (a.size() == 4 && a[0] == "scatter") {
    // The loader (and setCell) refuse such a scatter: written with a marker value, whose
    // raw f64 bits are then replaced in the file and its checksum made again.
    const ndtom::NdtMap in = ndtom::loadMap(a[1]);
    ndtom::MapOptions options = in.options();
    options.scan.memory_budget = kWriterBudget;
    ndtom::NdtMap out(options);
    const double marker = 0.00123456789012345, value = std::stod(a[3]);
    size_t changed = 0;
    in.forEachCell([&](const ndtom::CellView& c) {
      ndtom::CellStats stats = c.stats ? *c.stats : ndtom::CellStats{};
      if (stats.hasGaussian()) {
        stats.scatter = Eigen::Matrix3d::Identity() * marker;
        ++changed;
      }
      out.setCell(c.index, c.logodds, stats);
    });
    std::vector<uint8_t> bytes = ndtom::encodeMap(out);
    uint8_t from[8], to[8];
    std::memcpy(from, &marker, 8);
    std::memcpy(to, &value, 8);
    size_t replaced = 0;
    for (size_t i = 0; i + 8 <= bytes.size() - 4; ++i)
      if (std::memcmp(&bytes[i], from, 8) == 0) {
        std::memcpy(&bytes[i], to, 8);
        ++replaced;
        i += 7;
      }
    const uint32_t crc = ndtom::crc32(bytes.data(), bytes.size() - 4);
    for (int k = 0; k < 4; ++k) bytes[bytes.size() - 4 + k] = uint8_t(crc >> (8 * k));
    std::FILE* f = std::fopen(a[2].c_str(), "wb");
    if (!f || std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() || std::fclose(f) != 0)
      throw std::runtime_error("cannot write " + a[2]);
    std::printf("wrote %s: %zu Gaussians with scatter diag(%g) (%zu values)\n", a[2].c_str(),
                changed, value, replaced);
    return 0;
  }
  throw std::invalid_argument("--write: unknown command (see hostile_maps.h)");
}

}  // namespace

int writeHostileMap(const std::vector<std::string>& args) {
  try {
    return run(args);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ndtom-redteam --write: %s\n", e.what());
    return 1;
  }
}

}  // namespace redteam
