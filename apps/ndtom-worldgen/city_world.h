// A procedural city for testing at scale without downloading data: a grid of blocks separated
// by streets, each block cut into lots with a building (a box of random footprint and height)
// or a small park with trees, and along the curbs poles and parked cars. Deterministic: the
// same seed and size give the same world on any machine. Rays are cast against it exactly
// (boxes and the ground plane), through a 2D grid of the boxes so that a city of any size
// costs the same per ray.
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
};

class CityWorld {
 public:
  /// Throws std::invalid_argument for sizes that leave no room for blocks.
  explicit CityWorld(const CityLayout& layout);

  const CityLayout& layout() const { return layout_; }
  const std::vector<Box>& boxes() const { return boxes_; }

  /// Distance along `direction` (unit) from `origin` to the first surface (a box or the
  /// ground, z = 0) within `max_range`, or nothing.
  std::optional<double> castRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                double max_range) const;
  /// Whether `p` is inside a box (or below the ground).
  bool isInside(const Eigen::Vector3d& p) const;

 private:
  void addBox(const Box& box);
  const std::vector<uint32_t>& cellBoxes(int cx, int cy) const;

  CityLayout layout_;
  std::vector<Box> boxes_;
  // Boxes by the 2D cells their footprint overlaps, kCell metres square.
  static constexpr double kCell = 8.0;
  Eigen::Vector2d grid_origin_;
  int cells_x_ = 0, cells_y_ = 0;
  std::vector<std::vector<uint32_t>> cells_;
};

/// Where a ray (origin o, inverse direction) enters `box`, within [0, t_max], or nothing.
std::optional<double> rayBoxEntry(const Eigen::Vector3d& o, const Eigen::Vector3d& inverse_dir,
                                  const Box& box, double t_max);

}  // namespace ndtom::world
