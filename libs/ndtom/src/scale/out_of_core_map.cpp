#include "ndtom/scale/out_of_core_map.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "ndtom/files/map_io.h"
#include "ndtom/map/block_grid.h"
#include "ndtom/scale/block_moves.h"
#include "ndtom_internal/input_file.h"
#include "scale/spill_codec.h"

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
         std::to_string(t.z) + ".spill";
}

Eigen::AlignedBox3d OutOfCoreMap::tileBox(const CellIndex& t) const {
  return tileBoxOf(t, tile_blocks_, resident_.options().resolution);
}

NdtMap OutOfCoreMap::extractTile(const CellIndex& t) {
  const CellIndex lo{t.x * tile_blocks_, t.y * tile_blocks_, t.z * tile_blocks_};
  const CellIndex hi{lo.x + tile_blocks_ - 1, lo.y + tile_blocks_ - 1, lo.z + tile_blocks_ - 1};
  return extractBlockRange(resident_, lo, hi);
}

namespace {

// Calls f(tile) for every tile of `tile_blocks` blocks whose box meets `box`, if there are at
// most `limit` tiles to test (the box's tile range, widened by a tile each side so rounding
// cannot lose one); else returns false, calling nothing (also for a box that is not finite).
// Callers fall back to a pass over what they hold: a scan's box can be far larger than the
// map (a glitch point kilometres away, cut only at max_range).
template <class F>
bool forEachTileMeeting(const Eigen::AlignedBox3d& box, int tile_blocks, double resolution,
                        double limit, F&& f) {
  if (!box.min().allFinite() || !box.max().allFinite()) return false;
  const double edge = tile_blocks * kBlockEdge * resolution;
  CellIndex lo, hi;
  double tiles = 1;
  for (int a = 0; a < 3; ++a) {
    const double l = std::floor(box.min()[a] / edge) - 1, h = std::floor(box.max()[a] / edge) + 1;
    tiles *= h - l + 1;
    if (!(tiles <= limit) || l < -double(1 << 30) || h > double(1 << 30)) return false;
    lo[a] = int32_t(l), hi[a] = int32_t(h);
  }
  for (int32_t x = lo.x; x <= hi.x; ++x)
    for (int32_t y = lo.y; y <= hi.y; ++y)
      for (int32_t z = lo.z; z <= hi.z; ++z)
        if (const CellIndex t{x, y, z}; tileBoxOf(t, tile_blocks, resolution).intersects(box)) f(t);
  return true;
}

}  // namespace

std::vector<CellIndex> OutOfCoreMap::spilledTilesMeeting(const Eigen::AlignedBox3d& box) const {
  std::vector<CellIndex> out;
  const auto keep = [&](const CellIndex& t) {
    if (spilled_.count(t)) out.push_back(t);
  };
  if (!forEachTileMeeting(box, tile_blocks_, resident_.options().resolution,
                          double(spilled_.size()), keep))
    for (const CellIndex& t : spilled_)
      if (tileBox(t).intersects(box)) out.push_back(t);
  return out;
}

void OutOfCoreMap::noteTilesUsed(const Eigen::AlignedBox3d& box) {
  // The tiles the scan may have reached are the most recently used, and any new block is in
  // one of them: the scan's box says which tiles to note, or, if it has more tiles than the
  // resident map has blocks, a pass over the blocks does.
  const auto note = [&](const CellIndex& t) { last_use_[t] = clock_; };
  if (forEachTileMeeting(box, tile_blocks_, resident_.options().resolution,
                         double(resident_.numBlocks()), note))
    return;
  resident_.forEachBlock(
      [&](const CellIndex& block) { last_use_.try_emplace(tileOfBlock(block, tile_blocks_), clock_); });
  for (auto& [t, used] : last_use_)
    if (tileBox(t).intersects(box)) used = clock_;
}

NdtMap OutOfCoreMap::readSpilled(const CellIndex& t) const {
  const std::string path = spillPath(t);
  return SpillCodec::read(readInputFile(path, UINT64_MAX, "spill file"), resident_.options(), path);
}

void OutOfCoreMap::loadTile(CellIndex t) {  // a copy: t may be a key of spilled_
  absorbBlocks(resident_, readSpilled(t));
  std::remove(spillPath(t).c_str());
  spilled_.erase(t);
  last_use_[t] = clock_;
  ++stats_.loads;
}

void OutOfCoreMap::spillTile(CellIndex t) {  // a copy: t may be a key of last_use_
  NdtMap tile = extractTile(t);
  last_use_.erase(t);
  if (tile.isEmpty()) return;
  try {
    // Not synced to disk: a spill file lives only as long as this process.
    std::ofstream out(spillPath(t), std::ios::binary | std::ios::trunc);
    SpillCodec::write(tile, [&](const uint8_t* data, size_t n) {
      out.write(reinterpret_cast<const char*>(data), std::streamsize(n));
    });
    out.close();
    if (!out) throw std::runtime_error("cannot write the spill file " + spillPath(t));
  } catch (...) {
    absorbBlocks(resident_, std::move(tile));  // nothing lost: the tile stays in memory
    last_use_[t] = clock_;
    throw;
  }
  spilled_.insert(t);
  stats_.spilled_bytes += std::filesystem::file_size(spillPath(t));
  ++stats_.spills;
}

InsertionReport OutOfCoreMap::insertScan(const std::vector<Eigen::Vector3d>& points,
                                         const Eigen::Vector3d& origin,
                                         const ScanOptions& options) {
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

  for (const CellIndex& t : spilledTilesMeeting(box)) loadTile(t);
  const InsertionReport report = resident_.insertScan(points, origin, options);
  ++clock_;
  noteTilesUsed(box);
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
      visit(t, readSpilled(t));
      continue;
    }
    NdtMap tile = extractTile(t);
    if (tile.isEmpty()) continue;  // a tile the last scans' boxes met but never filled
    try {
      visit(t, tile);
    } catch (...) {
      absorbBlocks(resident_, std::move(tile));
      throw;
    }
    absorbBlocks(resident_, std::move(tile));
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
