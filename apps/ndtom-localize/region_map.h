// The part of a tiled map (ndtom/files/tiled_map_io.h) around the robot, for localizing in a map of
// any size: the tiles within a radius (in x-y) of where the robot is predicted to be are
// resident, those beyond the radius plus a tile's edge are dropped (the margin keeps a robot
// driving along a tile's edge from loading and dropping it over and over).
#pragma once

#include <Eigen/Core>
#include <set>
#include <string>
#include <vector>

#include "ndtom/files/tiled_map_io.h"

namespace ndtom::localizer {

class RegionMap {
 public:
  /// Opens the tiled file (its index only); throws as TiledMapFile. The resident tiles take
  /// at most `memory_budget` bytes: a tile past it is refused (MemoryBudgetError).
  RegionMap(const std::string& path, double radius,
            uint64_t memory_budget = ndtom::defaultMemoryBudget());

  /// The resident tiles, in one map: the same object for the whole run.
  const ndtom::NdtMap& map() const { return map_; }
  const ndtom::TiledMapFile& file() const { return file_; }
  double radius() const { return radius_; }

  /// Makes the tiles within the radius of `position` resident and drops the far ones.
  void keepAround(const Eigen::Vector3d& position);
  /// Every tile resident (a global search of the whole map).
  void keepEverything();
  /// Adds the tiles within the radius of any point of `path`, dropping none (a picture of
  /// where the robot went).
  void addAlong(const std::vector<Eigen::Vector3d>& path);

  size_t residentTiles() const { return resident_.size(); }
  size_t loads() const { return loads_; }
  size_t drops() const { return drops_; }
  /// Blocks the drops have looked at, for tests of their scaling: at most the resident
  /// blocks once per call, however many tiles it drops.
  size_t blocksExamined() const { return blocks_examined_; }

 private:
  double distanceXY(const ndtom::CellIndex& tile, const Eigen::Vector3d& p) const;
  void load(const ndtom::TileInfo& tile);
  void drop(const std::vector<ndtom::CellIndex>& tiles);

  ndtom::TiledMapFile file_;
  double radius_;
  ndtom::NdtMap map_;
  std::set<ndtom::CellIndex> resident_;
  size_t loads_ = 0, drops_ = 0, blocks_examined_ = 0;
};

}  // namespace ndtom::localizer
