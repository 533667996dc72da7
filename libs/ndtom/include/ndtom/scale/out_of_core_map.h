// Building a map larger than the memory it may use: the map is cut into tiles (tiled_map.h);
// tiles no scan has touched for the longest are written to a spill folder when the resident
// map exceeds its budget, and read back before a scan whose rays may reach them. A scan only
// changes cells between its sensor origin and its points (cut at max_range), so with every
// tile of that box resident each scan updates exactly the cells it would update in a map held
// whole: the result is the in-memory map, bit for bit.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "ndtom/files/tiled_map_io.h"
#include "ndtom/map/ndt_map.h"

namespace ndtom {

class OutOfCoreMap {
 public:
  struct Stats {
    size_t spills = 0, loads = 0;      ///< tiles written out, read back
    uint64_t spilled_bytes = 0;        ///< written in all
    size_t peak_resident_bytes = 0;    ///< the resident map's memoryBytes() at its largest
  };

  /// Keeps at most about `resident_budget` bytes of map in memory (plus the tiles the current
  /// scan needs), spilling tiles of `tile_blocks` blocks a side into `spill_folder` (created;
  /// the files this map writes are removed with it). Throws std::invalid_argument for bad
  /// sizes, std::runtime_error if the folder cannot be created.
  OutOfCoreMap(const MapOptions& options, uint64_t resident_budget, int tile_blocks,
               std::string spill_folder);
  ~OutOfCoreMap();
  OutOfCoreMap(const OutOfCoreMap&) = delete;
  OutOfCoreMap& operator=(const OutOfCoreMap&) = delete;

  /// NdtMap::insertScan with the tiles the scan may reach resident; then spills the least
  /// recently used others while over the budget.
  InsertionReport insertScan(const std::vector<Eigen::Vector3d>& points,
                             const Eigen::Vector3d& sensor_origin, const ScanOptions& options);

  /// Writes the whole map as a tiled file, one tile in memory at a time besides the resident
  /// ones.
  void saveTiled(const std::string& path);
  /// Shows every tile holding cells, in tile order, each as a map of its own: a spilled tile
  /// read into memory for the call (it stays spilled), a resident one lent and put back.
  void forEachTile(const TileSink& visit);
  /// Reads every spilled tile back: the whole map in memory (for the single-file format).
  NdtMap& assemble();

  const NdtMap& resident() const { return resident_; }
  const Stats& stats() const { return stats_; }
  size_t spilledTiles() const { return spilled_.size(); }

 private:
  std::string spillPath(const CellIndex& tile) const;
  /// The spilled tiles a scan's box meets (to read back before the scan).
  std::vector<CellIndex> spilledTilesMeeting(const Eigen::AlignedBox3d& box) const;
  /// Marks the tiles a scan's box meets as used by the current scan (clock_).
  void noteTilesUsed(const Eigen::AlignedBox3d& box);
  void loadTile(CellIndex tile);
  NdtMap readSpilled(const CellIndex& tile) const;
  void spillTile(CellIndex tile);
  Eigen::AlignedBox3d tileBox(const CellIndex& tile) const;
  /// The resident blocks of a tile, taken out of the resident map.
  NdtMap extractTile(const CellIndex& tile);

  NdtMap resident_;
  uint64_t budget_;
  int tile_blocks_;
  std::string folder_;
  /// Resident tiles and the scan that last used them: every tile holding blocks, and tiles
  /// a scan's box met that may hold none.
  std::map<CellIndex, uint64_t> last_use_;
  std::set<CellIndex> spilled_;
  uint64_t clock_ = 0;
  Stats stats_;
};

}  // namespace ndtom
