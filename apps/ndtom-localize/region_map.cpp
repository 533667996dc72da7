#include "region_map.h"

#include <cmath>
#include <stdexcept>
#include <unordered_set>

#include "ndtom/map/memory_budget.h"
#include "ndtom/map/tile_index.h"
#include "ndtom/scale/block_moves.h"

namespace ndtom::localizer {

namespace {

ndtom::MapOptions withBudget(ndtom::MapOptions options, uint64_t memory_budget) {
  options.scan.memory_budget = memory_budget;
  return options;
}

}  // namespace

RegionMap::RegionMap(const std::string& path, double radius, uint64_t memory_budget)
    : file_(path), radius_(radius), map_(withBudget(file_.options(), memory_budget)) {
  if (!(radius > 0)) throw std::invalid_argument("region radius must be positive");
}

double RegionMap::distanceXY(const ndtom::CellIndex& tile, const Eigen::Vector3d& p) const {
  const Eigen::AlignedBox3d box = file_.tileBox(tile);
  const double dx = std::max({box.min().x() - p.x(), 0.0, p.x() - box.max().x()});
  const double dy = std::max({box.min().y() - p.y(), 0.0, p.y() - box.max().y()});
  return std::hypot(dx, dy);
}

// Within the map's memory budget, or refused naming the tile: a region of many tiles (a
// whole-map search) must not grow past it unnoticed.
void RegionMap::load(const ndtom::TileInfo& tile) {
  const uint64_t budget = map_.options().scan.memory_budget;
  ndtom::NdtMap cells = file_.loadTile(tile, budget);
  const uint64_t need = uint64_t(map_.memoryBytes()) + cells.memoryBytes();
  if (need > budget)
    throw ndtom::MemoryBudgetError(file_.tileSource(tile) + " with the " +
                                       std::to_string(resident_.size()) + " tiles resident",
                                   need, budget);
  ndtom::absorbBlocks(map_, std::move(cells));
  resident_.insert(tile.tile);
  ++loads_;
}

// All at once: one pass over the resident blocks, or a lookup per block of each tile where
// that is less. Tile by tile over every block was quadratic (20k tiles: 27 s a scan).
void RegionMap::drop(const std::vector<ndtom::CellIndex>& tiles) {
  if (tiles.empty()) return;
  const int b = file_.tileBlocks();
  const size_t tile_blocks = size_t(b) * size_t(b) * size_t(b);
  if (tiles.size() * tile_blocks <= map_.numBlocks()) {
    for (const ndtom::CellIndex& t : tiles) {
      blocks_examined_ += tile_blocks;  // extractBlockRange looks each one up
      ndtom::extractBlockRange(map_, {t.x * b, t.y * b, t.z * b},
                               {t.x * b + b - 1, t.y * b + b - 1, t.z * b + b - 1});
    }
  } else {
    const std::unordered_set<ndtom::CellIndex, ndtom::CellIndexHash> far(tiles.begin(),
                                                                         tiles.end());
    ndtom::extractBlocks(map_, [&](const ndtom::CellIndex& block) {
      ++blocks_examined_;
      return far.count(ndtom::tileOfBlock(block, b)) > 0;
    });
  }
  for (const ndtom::CellIndex& t : tiles) resident_.erase(t);
  drops_ += tiles.size();
}

void RegionMap::keepAround(const Eigen::Vector3d& position) {
  const double keep = radius_ + file_.tileEdgeMetres();
  std::vector<ndtom::CellIndex> far;
  for (const ndtom::CellIndex& tile : resident_)
    if (distanceXY(tile, position) > keep) far.push_back(tile);
  drop(far);
  for (const ndtom::TileInfo& t : file_.tiles())
    if (!resident_.count(t.tile) && distanceXY(t.tile, position) <= radius_) load(t);
}

void RegionMap::keepEverything() {
  for (const ndtom::TileInfo& t : file_.tiles())
    if (!resident_.count(t.tile)) load(t);
}

void RegionMap::addAlong(const std::vector<Eigen::Vector3d>& path) {
  for (const ndtom::TileInfo& t : file_.tiles()) {
    if (resident_.count(t.tile)) continue;
    for (const Eigen::Vector3d& p : path)
      if (distanceXY(t.tile, p) <= radius_) {
        load(t);
        break;
      }
  }
}

}  // namespace ndtom::localizer
