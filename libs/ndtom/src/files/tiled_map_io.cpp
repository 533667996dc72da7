#include "ndtom/files/tiled_map_io.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

#include "ndtom/map/block_grid.h"
#include "ndtom/map/option_table.h"
#include "ndtom_internal/atomic_file.h"
#include "ndtom_internal/crc32.h"

namespace ndtom {
namespace {

constexpr char kMagic[8] = {'N', 'D', 'T', 'O', 'M', 'T', 'I', 'L'};
constexpr uint32_t kVersion = 1;
constexpr size_t kIndexEntryBytes = 3 * 4 + 3 * 8;
constexpr size_t kTrailerBytes = 8 + 4;

void putU32(std::string& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(char(uint8_t(v >> (8 * i))));
}
void putU64(std::string& out, uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(char(uint8_t(v >> (8 * i))));
}
uint64_t getLE(const std::string& in, size_t at, int bytes) {
  uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v |= uint64_t(uint8_t(in[at + size_t(i)])) << (8 * i);
  return v;
}

std::string optionsBlock(const MapOptions& options) {
  const std::vector<uint8_t> bytes = encodeMap(NdtMap(options));
  return std::string(bytes.begin(), bytes.end());
}

void copyCell(const CellView& c, NdtMap& to) {
  to.setCell(c.index, c.logodds, c.stats ? *c.stats : CellStats{});
}

}  // namespace

Eigen::AlignedBox3d tileBoxOf(const CellIndex& tile, int tile_blocks, double resolution) {
  const double edge = tile_blocks * kBlockEdge * resolution;
  const Eigen::Vector3d lo(tile.x * edge, tile.y * edge, tile.z * edge);
  return {lo, lo + Eigen::Vector3d::Constant(edge)};
}

void checkTileBlocks(int tile_blocks, const std::string& what) {
  if (tile_blocks < 1 || tile_blocks > kMaxTileBlocks)
    throw std::invalid_argument(what + ": tile_blocks " + std::to_string(tile_blocks) +
                                " is not in 1.." + std::to_string(kMaxTileBlocks));
}

void saveTiledMap(const MapOptions& map_options, const std::string& path, int tile_blocks,
                  const std::function<void(const TileSink&)>& fill) {
  checkTileBlocks(tile_blocks, "tiled map");
  std::string header(kMagic, sizeof kMagic);
  putU32(header, kVersion);
  putU32(header, uint32_t(tile_blocks));
  const std::string options = optionsBlock(map_options);
  putU64(header, options.size());
  header += options;
  writeFileAtomically(path, [&](const FileSink& sink) {
    sink(header.data(), header.size());
    std::string index;
    uint64_t offset = header.size(), count = 0;
    std::optional<CellIndex> last;
    fill([&](const CellIndex& key, const NdtMap& tile) {
      if (last && !(*last < key)) throw std::invalid_argument("tiled map: tiles out of order");
      if (firstDifference(tile.options(), map_options, OptionScope::Map))
        throw std::invalid_argument("tiled map: a tile with other options than the map");
      tile.forEachCell([&](const CellView& c) {
        if (tileOfCell(c.index, tile_blocks) != key)
          throw std::invalid_argument("tiled map: a cell outside its tile");
      });
      last = key;
      if (tile.isEmpty()) return;
      uint64_t size = 0;
      encodeMap(tile, [&](const uint8_t* data, size_t n) {
        sink(data, n);
        size += n;
      });
      for (const int32_t k : {key.x, key.y, key.z}) putU32(index, uint32_t(k));
      putU64(index, offset);
      putU64(index, size);
      putU64(index, tile.numCells());
      offset += size;
      ++count;
    });
    std::string tail;
    putU64(tail, count);
    tail += index;
    putU64(tail, offset);
    const uint32_t crc = crc32(tail.data(), tail.size(), crc32(header.data(), header.size()));
    putU32(tail, crc);
    sink(tail.data(), tail.size());
  });
}

void saveTiledMap(const NdtMap& map, const std::string& path, int tile_blocks) {
  checkTileBlocks(tile_blocks, "tiled map");
  std::map<CellIndex, NdtMap> tiles;  // ordered: the index's order
  map.forEachCellOrdered([&](const CellView& c) {
    const CellIndex key = tileOfCell(c.index, tile_blocks);
    auto it = tiles.find(key);
    if (it == tiles.end()) it = tiles.emplace(key, NdtMap(map.options())).first;
    copyCell(c, it->second);
  });
  saveTiledMap(map.options(), path, tile_blocks, [&](const TileSink& sink) {
    for (auto& [key, tile] : tiles) {
      tile.shrinkToFit();
      sink(key, tile);
    }
  });
}

TiledMapFile::TiledMapFile(std::string path) : path_(std::move(path)) {
  const auto bad = [&](const std::string& why) {
    return MapFormatError(path_ + ": not a valid tiled map (" + why + ")");
  };
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path_, ec))
    throw std::runtime_error("cannot read " + path_ + ": not a regular file");
  const uint64_t file_size = std::filesystem::file_size(path_, ec);
  std::ifstream in(path_, std::ios::binary);
  if (ec || !in) throw std::runtime_error("cannot read " + path_);
  const auto readAt = [&](uint64_t at, uint64_t n) {
    std::string bytes(n, '\0');
    in.seekg(std::streamoff(at));
    if (!in.read(bytes.data(), std::streamsize(n)))
      throw std::runtime_error("cannot read " + path_);
    return bytes;
  };
  constexpr size_t kFixed = sizeof kMagic + 4 + 4 + 8;
  if (file_size < kFixed + kTrailerBytes + 8) throw bad("too short");
  std::string header = readAt(0, kFixed);
  if (std::memcmp(header.data(), kMagic, sizeof kMagic) != 0) throw bad("no NDTOMTIL magic");
  if (getLE(header, 8, 4) != kVersion)
    throw bad("version " + std::to_string(getLE(header, 8, 4)) + ", this reads 1");
  tile_blocks_ = int(std::min<uint64_t>(getLE(header, 12, 4), kMaxTileBlocks + 1));
  if (tile_blocks_ < 1 || tile_blocks_ > kMaxTileBlocks) throw bad("tile size out of range");
  const uint64_t options_size = getLE(header, 16, 8);
  if (options_size > file_size - kFixed - kTrailerBytes - 8) throw bad("options size");
  const std::string options = readAt(kFixed, options_size);
  header += options;

  const std::string trailer = readAt(file_size - kTrailerBytes, kTrailerBytes);
  const uint64_t index_at = getLE(trailer, 0, 8);
  if (index_at < header.size() || index_at > file_size - kTrailerBytes - 8)
    throw bad("index offset");
  const std::string index = readAt(index_at, file_size - kTrailerBytes - index_at);
  const uint32_t crc = crc32(
      trailer.data(), 8, crc32(index.data(), index.size(), crc32(header.data(), header.size())));
  if (crc != uint32_t(getLE(trailer, 8, 4))) throw bad("index checksum mismatch");
  // The checksum holds: the options and the index are as written.
  options_ = decodeMap(reinterpret_cast<const uint8_t*>(options.data()), options.size(),
                       path_ + " (options)")
                 .options();
  const uint64_t count = getLE(index, 0, 8);
  if (count > (index.size() - 8) / kIndexEntryBytes || 8 + count * kIndexEntryBytes != index.size())
    throw bad("index size");
  uint64_t expected_offset = header.size();
  tiles_.reserve(size_t(count));
  for (uint64_t i = 0; i < count; ++i) {
    const size_t at = size_t(8 + i * kIndexEntryBytes);
    TileInfo t;
    t.tile = {int32_t(uint32_t(getLE(index, at, 4))), int32_t(uint32_t(getLE(index, at + 4, 4))),
              int32_t(uint32_t(getLE(index, at + 8, 4)))};
    t.offset = getLE(index, at + 12, 8);
    t.size = getLE(index, at + 20, 8);
    t.cells = getLE(index, at + 28, 8);
    if (t.offset != expected_offset || t.size > index_at - t.offset) throw bad("tile offsets");
    if (!tiles_.empty() && !(tiles_.back().tile < t.tile)) throw bad("tiles out of order");
    expected_offset += t.size;
    tiles_.push_back(t);
  }
  if (expected_offset != index_at) throw bad("bytes between the tiles and the index");
}

double TiledMapFile::tileEdgeMetres() const {
  return tile_blocks_ * kBlockEdge * options_.resolution;
}

Eigen::AlignedBox3d TiledMapFile::tileBox(const CellIndex& tile) const {
  return tileBoxOf(tile, tile_blocks_, options_.resolution);
}

std::string TiledMapFile::tileSource(const TileInfo& tile) const {
  return path_ + " tile (" + std::to_string(tile.tile.x) + ", " + std::to_string(tile.tile.y) +
         ", " + std::to_string(tile.tile.z) + ")";
}

NdtMap TiledMapFile::loadTile(const TileInfo& tile, uint64_t memory_budget) const {
  const std::string source = tileSource(tile);
  if (tile.size > memory_budget)
    throw MemoryBudgetError("loading " + source, tile.size, memory_budget);
  std::ifstream in(path_, std::ios::binary);
  std::string bytes(tile.size, '\0');
  in.seekg(std::streamoff(tile.offset));
  if (!in || !in.read(bytes.data(), std::streamsize(tile.size)))
    throw std::runtime_error("cannot read " + source);
  NdtMap map = decodeMap(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), source,
                         memory_budget);
  if (firstDifference(map.options(), options_, OptionScope::Map))
    throw MapFormatError(source + ": options differ from the file's");
  size_t cells = 0;
  map.forEachCell([&](const CellView& c) {
    if (tileOfCell(c.index, tile_blocks_) != tile.tile)
      throw MapFormatError(source + ": a cell outside the tile");
    ++cells;
  });
  if (cells != tile.cells) throw MapFormatError(source + ": cell count differs from the index");
  return map;
}

void TiledMapFile::addTile(const NdtMap& tile, NdtMap& map) {
  if (firstDifference(tile.options(), map.options(), OptionScope::Map))
    throw std::invalid_argument("tiled map: a tile with other options than the map");
  tile.forEachCellOrdered([&](const CellView& c) {
    if (map.cell(c.index)) throw std::invalid_argument("tiled map: a tile's cell is already known");
  });
  tile.forEachCellOrdered([&](const CellView& c) { copyCell(c, map); });
  map.shrinkToFit();
}

NdtMap TiledMapFile::loadRegion(const Eigen::AlignedBox3d& region, uint64_t memory_budget) const {
  return loadTilesWhere([&](const CellIndex& t) { return tileBox(t).intersects(region); },
                        memory_budget);
}

NdtMap TiledMapFile::loadAll(uint64_t memory_budget) const {
  return loadTilesWhere([](const CellIndex&) { return true; }, memory_budget);
}

NdtMap TiledMapFile::loadTilesWhere(const std::function<bool(const CellIndex&)>& wanted,
                                    uint64_t memory_budget) const {
  MapOptions options = options_;
  options.scan.memory_budget = memory_budget;
  NdtMap map(options);
  for (const TileInfo& t : tiles_) {
    if (!wanted(t.tile)) continue;
    NdtMap tile = loadTile(t, memory_budget);
    const uint64_t need = uint64_t(map.memoryBytes()) + tile.memoryBytes();
    if (need > memory_budget)
      throw MemoryBudgetError(tileSource(t) + " with the tiles before it", need, memory_budget);
    addTile(tile, map);
  }
  return map;
}

}  // namespace ndtom
