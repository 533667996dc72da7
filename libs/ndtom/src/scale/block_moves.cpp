#include "ndtom/scale/block_moves.h"

#include <algorithm>
#include <stdexcept>

#include "map/map_internals.h"

namespace ndtom {

namespace {

using Blocks = BlockGrid<MapBlock>::Map;

// Moves one block into `to`; returns the iterator after it.
Blocks::iterator moveBlock(NdtMap& from, Blocks::iterator it, NdtMap& to) {
  const size_t cells = it->second->known.count(), bytes = statsBytes(it->second->stats);
  MapInternals::grid(to).blocks().emplace(it->first, std::move(it->second));
  MapInternals::countBlocks(to, cells, bytes);
  MapInternals::countBlocks(from, 0 - cells, 0 - bytes);
  return MapInternals::grid(from).blocks().erase(it);
}

void finishExtraction(NdtMap& from, NdtMap& out) {
  if (out.numBlocks() == 0) return;
  // The buckets of the blocks that left are memory too.
  MapInternals::grid(from).blocks().rehash(0);
  MapInternals::touch(from);
  MapInternals::touch(out);
}

}  // namespace

NdtMap extractBlocks(NdtMap& map, const std::function<bool(const CellIndex& block)>& take) {
  NdtMap out(map.options());
  Blocks& blocks = MapInternals::grid(map).blocks();
  for (auto it = blocks.begin(); it != blocks.end();)
    it = take(it->first) ? moveBlock(map, it, out) : std::next(it);
  finishExtraction(map, out);
  return out;
}

NdtMap extractBlockRange(NdtMap& map, const CellIndex& lo, const CellIndex& hi) {
  auto inRange = [&](const CellIndex& b) {
    return b.x >= lo.x && b.x <= hi.x && b.y >= lo.y && b.y <= hi.y && b.z >= lo.z && b.z <= hi.z;
  };
  double range_blocks = 1;
  for (int a = 0; a < 3; ++a) range_blocks *= std::max(0.0, double(hi[a]) - double(lo[a]) + 1);
  if (range_blocks > double(map.numBlocks())) return extractBlocks(map, inRange);
  NdtMap out(map.options());
  Blocks& blocks = MapInternals::grid(map).blocks();
  for (int32_t x = lo.x; x <= hi.x; ++x)
    for (int32_t y = lo.y; y <= hi.y; ++y)
      for (int32_t z = lo.z; z <= hi.z; ++z)
        if (auto it = blocks.find(CellIndex{x, y, z}); it != blocks.end()) moveBlock(map, it, out);
  finishExtraction(map, out);
  return out;
}

NdtMap copyBlocks(const NdtMap& map, const std::function<bool(const CellIndex& block)>& take,
                  bool statistics_only) {
  NdtMap out(map.options());
  Blocks& blocks = MapInternals::grid(out).blocks();
  for (const auto& [index, block] : MapInternals::grid(map).blocks()) {
    if ((statistics_only && block->stats.empty()) || !take(index)) continue;
    auto copy = std::make_unique<MapBlock>(*block);
    MapInternals::countBlocks(out, copy->known.count(), statsBytes(copy->stats));
    blocks.emplace(index, std::move(copy));
  }
  MapInternals::touch(out);
  return out;
}

void absorbBlocks(NdtMap& map, NdtMap&& other) {
  if (other.options().resolution != map.options().resolution)
    throw std::invalid_argument("absorbBlocks: the maps' resolutions differ");
  BlockGrid<MapBlock>& grid = MapInternals::grid(map);
  for (const auto& [index, block] : MapInternals::grid(other).blocks())
    if (grid.find(index)) throw std::invalid_argument("absorbBlocks: a block is in both maps");
  MapInternals::countBlocks(map, other.numCells(), MapInternals::statsBytes(other));
  for (auto& [index, block] : MapInternals::grid(other).blocks())
    grid.blocks().emplace(index, std::move(block));
  other.clear();
  MapInternals::touch(map);
}

}  // namespace ndtom
