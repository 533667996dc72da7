#include "ndtom/scale/block_moves.h"
#include "region_map.h"

#include <cmath>
#include <stdexcept>

namespace ndtom::localizer {

RegionMap::RegionMap(const std::string& path, double radius)
    : file_(path), radius_(radius), map_(file_.options()) {
  if (!(radius > 0)) throw std::invalid_argument("region radius must be positive");
}

double RegionMap::distanceXY(const ndtom::CellIndex& tile, const Eigen::Vector3d& p) const {
  const Eigen::AlignedBox3d box = file_.tileBox(tile);
  const double dx = std::max({box.min().x() - p.x(), 0.0, p.x() - box.max().x()});
  const double dy = std::max({box.min().y() - p.y(), 0.0, p.y() - box.max().y()});
  return std::hypot(dx, dy);
}

void RegionMap::load(const ndtom::TileInfo& tile) {
  ndtom::NdtMap cells = file_.loadTile(tile);
  ndtom::absorbBlocks(map_, std::move(cells));
  resident_.insert(tile.tile);
  ++loads_;
}

void RegionMap::drop(const ndtom::CellIndex& tile) {
  const int blocks = file_.tileBlocks();
  ndtom::extractBlocks(map_, [&](const ndtom::CellIndex& block) {
    return ndtom::tileOfBlock(block, blocks) == tile;
  });
  resident_.erase(tile);
  ++drops_;
}

void RegionMap::keepAround(const Eigen::Vector3d& position) {
  const double keep = radius_ + file_.tileEdgeMetres();
  for (auto it = resident_.begin(); it != resident_.end();) {
    const ndtom::CellIndex tile = *it++;
    if (distanceXY(tile, position) > keep) drop(tile);
  }
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
