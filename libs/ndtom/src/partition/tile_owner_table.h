// Which tiles one process of a distributed build owns (tile_ownership.h), as a table over a
// scan's box of tiles: a test is a few compares and a load, not a hash. Rays from one sensor
// cross the same few hundred tiles over and over, and the owned walk asks at every crossing.
#pragma once

#include <cstdint>
#include <vector>

#include "ndtom/map/cell_index.h"
#include "ndtom/partition/tile_ownership.h"

namespace ndtom {

class TileOwnerTable {
 public:
  /// No table: every test hashes (a single ray, or a box too large for a table).
  explicit TileOwnerTable(const TileOwnership& ownership) : ownership_(ownership) { setEdge(); }

  /// A table for the tiles of the cells in [cells_lo, cells_hi] and one tile around them (a
  /// ray's walk at the scale of tiles may step one past its end within rounding); tiles
  /// outside are hashed. No table if the box holds more than 2^20 tiles.
  TileOwnerTable(const TileOwnership& ownership, const CellIndex& cells_lo,
                 const CellIndex& cells_hi)
      : ownership_(ownership) {
    setEdge();
    const CellIndex lo = tileOf(cells_lo), hi = tileOf(cells_hi);
    lo_ = {lo.x - 1, lo.y - 1, lo.z - 1};
    const int64_t nx = int64_t(hi.x) - lo_.x + 2, ny = int64_t(hi.y) - lo_.y + 2,
                  nz = int64_t(hi.z) - lo_.z + 2;
    if (nx <= 0 || ny <= 0 || nz <= 0 || nx * ny * nz > (int64_t(1) << 20)) return;
    nx_ = uint64_t(nx), ny_ = uint64_t(ny), nz_ = uint64_t(nz);
    owned_.resize(nx_ * ny_ * nz_);
    size_t k = 0;
    for (int64_t z = 0; z < nz; ++z)
      for (int64_t y = 0; y < ny; ++y)
        for (int64_t x = 0; x < nx; ++x)
          owned_[k++] = ownership_.ownsTile(
              {int32_t(lo_.x + x), int32_t(lo_.y + y), int32_t(lo_.z + z)});
  }

  int32_t tileOf(int32_t cell) const { return Lookup::tileOf(cell, edge_, shift_); }
  CellIndex tileOf(const CellIndex& c) const { return {tileOf(c.x), tileOf(c.y), tileOf(c.z)}; }

  /// The test as a small value, which a hot loop copies and keeps in registers (through the
  /// object, every counter the loop writes could alias the table's bounds).
  struct Lookup {
    const uint8_t* owned;
    int64_t lo_x, lo_y, lo_z;
    uint64_t nx, ny, nz;
    const TileOwnership* ownership;
    int32_t edge;  ///< tile edge in cells
    int shift;     ///< log2(edge) for power-of-two edges, else -1

    int32_t tileOf(int32_t cell) const { return tileOf(cell, edge, shift); }
    static int32_t tileOf(int32_t cell, int32_t edge, int shift) {
      return shift >= 0 ? cell >> shift : floorDiv(cell, edge);
    }
    /// The table's index of a tile, -1 if the table does not hold it.
    int64_t indexOf(const CellIndex& tile) const {
      // Unsigned, so a tile below the box wraps to a large offset: one compare per axis.
      const uint64_t x = uint64_t(tile.x - lo_x), y = uint64_t(tile.y - lo_y),
                     z = uint64_t(tile.z - lo_z);
      if (!(x < nx && y < ny && z < nz)) return -1;
      return int64_t((z * ny + y) * nx + x);
    }
    /// Whether the table holds the tiles around this one too (false without a table).
    bool holdsAround(const CellIndex& tile) const {
      // Unsigned: below the box wraps to a large offset. A table is 3 tiles or more a side.
      return nx >= 3 && uint64_t(tile.x - lo_x - 1) < nx - 2 &&
             uint64_t(tile.y - lo_y - 1) < ny - 2 && uint64_t(tile.z - lo_z - 1) < nz - 2;
    }
    bool ownsTile(const CellIndex& tile) const {
      const int64_t i = indexOf(tile);
      return i >= 0 ? owned[i] != 0 : ownership->ownsTile(tile);
    }
    bool ownsCell(const CellIndex& cell) const {
      return ownsTile({tileOf(cell.x), tileOf(cell.y), tileOf(cell.z)});
    }
  };
  Lookup lookup() const {
    return {owned_.data(), lo_.x, lo_.y, lo_.z, nx_, ny_, nz_, &ownership_, edge_, shift_};
  }

  bool ownsTile(const CellIndex& tile) const { return lookup().ownsTile(tile); }
  bool ownsCell(const CellIndex& cell) const { return lookup().ownsCell(cell); }

 private:
  void setEdge() {
    edge_ = ownership_.tileCells();
    shift_ = (edge_ & (edge_ - 1)) == 0 ? __builtin_ctz(uint32_t(edge_)) : -1;
  }

  TileOwnership ownership_;
  int32_t edge_ = 0;
  int shift_ = -1;  ///< log2(edge_) for power-of-two edges
  std::vector<uint8_t> owned_;  ///< [(z * ny + y) * nx + x] from lo_
  CellIndex lo_{};
  uint64_t nx_ = 0, ny_ = 0, nz_ = 0;
};

}  // namespace ndtom
