#include "ndtom/out_of_core_map.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

#include "ndtom/block_grid.h"
#include "ndtom/map_io.h"

namespace ndtom {

OutOfCoreMap::OutOfCoreMap(const MapOptions& options, uint64_t resident_budget, int tile_blocks,
                           std::string spill_folder)
    : resident_(options), budget_(resident_budget), tile_blocks_(tile_blocks),
      folder_(std::move(spill_folder)) {
  checkTileBlocks(tile_blocks, "out-of-core map");
  if (resident_budget == 0) throw std::invalid_argument("out-of-core map: a budget of 0 bytes");
  std::error_code ec;
  std::filesystem::create_directories(folder_, ec);
  if (!std::filesystem::is_directory(folder_, ec))
    throw std::runtime_error("out-of-core map: cannot create the spill folder " + folder_);
}

OutOfCoreMap::~OutOfCoreMap() {
  for (const CellIndex& t : spilled_) std::remove(spillPath(t).c_str());
}

std::string OutOfCoreMap::spillPath(const CellIndex& t) const {
  return folder_ + "/tile_" + std::to_string(t.x) + "_" + std::to_string(t.y) + "_" +
         std::to_string(t.z) + ".ndtom";
}

Eigen::AlignedBox3d OutOfCoreMap::tileBox(const CellIndex& t) const {
  return tileBoxOf(t, tile_blocks_, resident_.options().resolution);
}

std::set<CellIndex> OutOfCoreMap::tilesMeeting(const Eigen::AlignedBox3d& box) const {
  std::set<CellIndex> out;
  for (const auto& [t, used] : last_use_)
    if (tileBox(t).intersects(box)) out.insert(t);
  for (const CellIndex& t : spilled_)
    if (tileBox(t).intersects(box)) out.insert(t);
  return out;
}

void OutOfCoreMap::loadTile(CellIndex t) {  // a copy: t may be a key of spilled_
  NdtMap tile = loadMap(spillPath(t), std::numeric_limits<uint64_t>::max());
  resident_.absorbBlocks(std::move(tile));
  std::remove(spillPath(t).c_str());
  spilled_.erase(t);
  last_use_[t] = clock_;
  ++stats_.loads;
}

void OutOfCoreMap::spillTile(CellIndex t) {  // a copy: t may be a key of last_use_
  NdtMap tile = resident_.extractBlocks(
      [&](const CellIndex& block) { return tileOfBlock(block, tile_blocks_) == t; });
  last_use_.erase(t);
  if (tile.isEmpty()) return;
  try {
    // Not synced to disk: a spill file lives only as long as this process.
    std::ofstream out(spillPath(t), std::ios::binary | std::ios::trunc);
    encodeMap(tile, [&](const uint8_t* data, size_t n) {
      out.write(reinterpret_cast<const char*>(data), std::streamsize(n));
    });
    out.close();
    if (!out) throw std::runtime_error("cannot write the spill file " + spillPath(t));
  } catch (...) {
    resident_.absorbBlocks(std::move(tile));  // nothing lost: the tile stays in memory
    last_use_[t] = clock_;
    throw;
  }
  spilled_.insert(t);
  stats_.spilled_bytes += std::filesystem::file_size(spillPath(t));
  ++stats_.spills;
}

InsertionReport OutOfCoreMap::insertScan(const std::vector<Eigen::Vector3d>& points,
                                         const Eigen::Vector3d& origin,
                                         const InsertOptions& options) {
  // Every cell a ray may change lies in the box of the origin and the points, each cut at
  // max_range; a cell of margin covers the rounding of points on a tile's face.
  Eigen::AlignedBox3d box(origin);
  for (const Eigen::Vector3d& p : points) {
    if (!p.allFinite()) continue;
    const double range = (p - origin).norm();
    box.extend(range > options.max_range ? Eigen::Vector3d(origin + (p - origin) * (options.max_range / range))
                                         : p);
  }
  const double margin = resident_.options().resolution;
  box.min().array() -= margin;
  box.max().array() += margin;

  const std::set<CellIndex> needed = tilesMeeting(box);
  for (const CellIndex& t : needed)
    if (spilled_.count(t)) loadTile(t);
  const InsertionReport report = resident_.insertScan(points, origin, options);
  // Every tile holding blocks is known (a scan may have started new ones), and the ones
  // the scan may have reached are the most recently used.
  ++clock_;
  resident_.forEachBlock(
      [&](const CellIndex& block) { last_use_.try_emplace(tileOfBlock(block, tile_blocks_), clock_); });
  for (auto& [t, used] : last_use_)
    if (tileBox(t).intersects(box)) used = clock_;
  stats_.peak_resident_bytes = std::max(stats_.peak_resident_bytes, resident_.memoryBytes());
  while (resident_.memoryBytes() > budget_) {
    const CellIndex* oldest = nullptr;
    uint64_t oldest_use = clock_;
    for (const auto& [t, used] : last_use_)
      if (used < oldest_use) oldest = &t, oldest_use = used;
    if (!oldest) break;  // only the current scan's tiles are left
    spillTile(*oldest);
  }
  return report;
}

void OutOfCoreMap::forEachTile(const TileSink& visit) {
  std::set<CellIndex> tiles(spilled_.begin(), spilled_.end());
  for (const auto& [t, used] : last_use_) tiles.insert(t);
  for (const CellIndex& t : tiles) {
    if (spilled_.count(t)) {
      visit(t, loadMap(spillPath(t), std::numeric_limits<uint64_t>::max()));
      continue;
    }
    NdtMap tile = resident_.extractBlocks(
        [&](const CellIndex& block) { return tileOfBlock(block, tile_blocks_) == t; });
    if (tile.isEmpty()) continue;  // a tile the last scans' boxes met but never filled
    try {
      visit(t, tile);
    } catch (...) {
      resident_.absorbBlocks(std::move(tile));
      throw;
    }
    resident_.absorbBlocks(std::move(tile));
  }
}

void OutOfCoreMap::saveTiled(const std::string& path) {
  saveTiledMap(resident_.options(), path, tile_blocks_,
               [&](const TileSink& sink) { forEachTile(sink); });
}

NdtMap& OutOfCoreMap::assemble() {
  while (!spilled_.empty()) loadTile(*spilled_.begin());
  return resident_;
}

}  // namespace ndtom
