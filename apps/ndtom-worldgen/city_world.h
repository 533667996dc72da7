// A procedural city for testing at scale without downloading data: a grid of blocks separated
// by streets, each block cut into lots with a building (a box of random footprint and height)
// or a small park with trees, and along the curbs poles and parked cars. Deterministic: the
// same seed and size give the same world on any machine. Rays are cast against it exactly
// (boxes and the ground plane), through a 2D grid of the boxes so that a city of any size
// costs the same per ray. Its memory grows with the blocks (estimatedBytes()): a few kB a
// block, and 4 bytes for each 8 m grid cell.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

namespace ndtom::world {

struct Box {
  Eigen::Vector3d lo, hi;  ///< (m) corners, lo < hi on every axis
};

struct CityLayout {
  int blocks_x = 8, blocks_y = 8;  ///< blocks per side; streets run between and around them
  double block_pitch = 80;         ///< (m) from one street's centre line to the next
  double street_width = 20;        ///< (m) curb to curb
  uint64_t seed = 1;
  /// Every block the same (the same lots, parks, poles and cars): look-alike streets, where
  /// a loop closure must not take one street for another.
  bool identical_blocks = false;
};

class CityWorld {
 public:
  /// Throws std::invalid_argument for sizes that leave no room for blocks.
  explicit CityWorld(const CityLayout& layout);

  /// What a city of `layout` will hold in memory at most while it is built (its boxes, the
  /// grid and their growth), in bytes: for refusing a city too large before building it.
  static uint64_t estimatedBytes(const CityLayout& layout);
  /// The bytes the city holds once built.
  uint64_t memoryBytes() const;

  const CityLayout& layout() const { return layout_; }
  const std::vector<Box>& boxes() const { return boxes_; }

  /// Distance along `direction` (unit) from `origin` to the first surface (a box or the
  /// ground, z = 0) within `max_range`, or nothing.
  std::optional<double> castRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                double max_range) const;
  /// Whether `p` is inside a box (or below the ground).
  bool isInside(const Eigen::Vector3d& p) const;

 private:
  struct CellRange {
    int x0, y0, x1, y1;  ///< grid cells a box's footprint overlaps, inclusive
  };
  struct BoxList {
    const uint32_t *first, *last;
    const uint32_t* begin() const { return first; }
    const uint32_t* end() const { return last; }
  };
  void addBox(const Box& box);
  CellRange cellsUnder(const Box& box) const;
  void buildGrid();
  BoxList cellBoxes(int cx, int cy) const;

  CityLayout layout_;
  std::vector<Box> boxes_;
  // Boxes by the 2D cells their footprint overlaps, kCell metres square.
  static constexpr double kCell = 8.0;
  Eigen::Vector2d grid_origin_;
  int cells_x_ = 0, cells_y_ = 0;
  // Boxes of cell c (y * cells_x_ + x): cell_boxes_[cell_start_[c] .. cell_start_[c + 1]).
  std::vector<uint32_t> cell_start_, cell_boxes_;
};

/// Where a ray (origin o, inverse direction) enters `box`, within [0, t_max], or nothing.
std::optional<double> rayBoxEntry(const Eigen::Vector3d& o, const Eigen::Vector3d& inverse_dir,
                                  const Box& box, double t_max);

}  // namespace ndtom::world
