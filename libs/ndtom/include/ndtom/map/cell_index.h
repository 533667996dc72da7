// One voxel convention for the whole library: cell i covers [i·r, (i+1)·r) on each axis,
// its centre is (i + ½)·r, and a point's cell is floor(x / r).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>

namespace ndtom {

struct CellIndex {
  int32_t x = 0, y = 0, z = 0;

  int32_t operator[](int axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
  int32_t& operator[](int axis) { return axis == 0 ? x : (axis == 1 ? y : z); }
  friend bool operator==(const CellIndex& a, const CellIndex& b) {
    return a.x == b.x && a.y == b.y && a.z == b.z;
  }
  friend bool operator!=(const CellIndex& a, const CellIndex& b) { return !(a == b); }
  friend bool operator<(const CellIndex& a, const CellIndex& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
  }
};

/// Per axis, the smaller and the larger index: the corners of the box holding both cells.
inline CellIndex cellwiseMin(const CellIndex& a, const CellIndex& b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
inline CellIndex cellwiseMax(const CellIndex& a, const CellIndex& b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}

struct CellIndexHash {
  size_t operator()(const CellIndex& c) const noexcept {
    // splitmix64 finaliser over the packed coordinates: cheap and well mixed.
    uint64_t h = (uint64_t(uint32_t(c.x)) * 0x9E3779B97F4A7C15ULL) ^
                 (uint64_t(uint32_t(c.y)) * 0xC2B2AE3D27D4EB4FULL) ^
                 (uint64_t(uint32_t(c.z)) * 0x165667B19E3779F9ULL);
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ULL;
    h ^= h >> 29;
    return size_t(h);
  }
};

/// Cells with |index| >= kMaxCellIndex are outside the supported range: points there are
/// rejected, never wrapped. At 0.1 m this is ±107,374 km, so UTM coordinates fit.
inline constexpr int32_t kMaxCellIndex = int32_t(1) << 30;

/// The one range rule for insertion, setCell(), saving and loading: |i| < kMaxCellIndex on
/// every axis. (Insertion accepted -(2^30 - 1) while setCell and the loader refused it, so a
/// map could be written that could not be read.)
[[nodiscard]] inline bool isSupportedCell(const CellIndex& c) {
  for (int a = 0; a < 3; ++a)
    if (!(c[a] > -kMaxCellIndex && c[a] < kMaxCellIndex)) return false;
  return true;
}

/// Maps metric coordinates to cells for one resolution.
class GridGeometry {
 public:
  explicit GridGeometry(double resolution = 0.2)
      : resolution_(resolution), inv_resolution_(1.0 / resolution) {}

  double resolution() const { return resolution_; }
  double invResolution() const { return inv_resolution_; }

  /// False for non-finite points and points whose cell is not isSupportedCell().
  [[nodiscard]] bool inRange(const Eigen::Vector3d& p) const {
    for (int a = 0; a < 3; ++a) {
      // floor(s) > -kMaxCellIndex and floor(s) < kMaxCellIndex; false for NaN too.
      const double s = p[a] * inv_resolution_;
      if (!(s >= -double(kMaxCellIndex - 1) && s < double(kMaxCellIndex))) return false;
    }
    return true;
  }

  /// Only valid for points with inRange(p).
  CellIndex cellOf(const Eigen::Vector3d& p) const { return floorCell(p * inv_resolution_); }

  /// The cell of a point already divided by the resolution (|coordinates| < kMaxCellIndex).
  static CellIndex floorCell(const Eigen::Vector3d& scaled) {
    return {floorToInt(scaled.x()), floorToInt(scaled.y()), floorToInt(scaled.z())};
  }

  double cellMin(int32_t i) const { return double(i) * resolution_; }

  Eigen::Vector3d cellCenter(const CellIndex& c) const {
    return {(c.x + 0.5) * resolution_, (c.y + 0.5) * resolution_, (c.z + 0.5) * resolution_};
  }

 private:
  static int32_t floorToInt(double v) {
    const auto i = static_cast<int32_t>(v);
    return i - (v < double(i));
  }

  double resolution_;
  double inv_resolution_;
};

/// Floor division for cell indices (k > 0), exact for negative indices too.
inline int32_t floorDiv(int32_t i, int32_t k) {
  const int32_t q = i / k;
  return (i % k != 0 && i < 0) ? q - 1 : q;
}

/// The index of the cube of `k` a side that holds `c`, on a grid `k` times coarser.
inline CellIndex cellwiseFloorDiv(const CellIndex& c, int32_t k) {
  return {floorDiv(c.x, k), floorDiv(c.y, k), floorDiv(c.z, k)};
}

}  // namespace ndtom
