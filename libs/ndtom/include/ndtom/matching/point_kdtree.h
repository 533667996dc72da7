// A static k-d tree over 3D points (built once, queried many times): the nearest Gaussian
// means of a scan point during registration, where a search radius of several cells makes
// a walk over neighbouring grid cells too slow.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace ndtom {

class PointKdTree {
 public:
  struct Neighbour {
    uint32_t index = 0;           ///< into the points given to the constructor
    double squared_distance = 0;  ///< m²
  };

  PointKdTree() = default;
  /// Copies the points; non-finite points are left out of the tree (never returned).
  explicit PointKdTree(const std::vector<Eigen::Vector3d>& points);

  size_t size() const { return points_.size(); }

  /// Up to `k` points nearest to `query` with squared distance <= `max_squared_distance`,
  /// nearest first; ties in distance are broken by the smaller index. Clears `out` first.
  void nearest(const Eigen::Vector3d& query, size_t k, double max_squared_distance,
               std::vector<Neighbour>& out) const;

 private:
  static constexpr uint32_t kLeafSize = 8;

  struct Node {
    uint32_t begin = 0, end = 0;   ///< range in order_ (leaves only)
    uint32_t left = 0, right = 0;  ///< child node indices (inner nodes only)
    int axis = -1;                 ///< split axis, -1 for a leaf
    double split = 0;              ///< left holds coordinates <= split, right >= split
  };

  uint32_t build(uint32_t begin, uint32_t end);
  void search(uint32_t node, const Eigen::Vector3d& query, size_t k, double& bound,
              std::vector<Neighbour>& out) const;

  std::vector<Eigen::Vector3d> points_;
  std::vector<uint32_t> order_;  ///< point indices, grouped by leaf
  std::vector<Node> nodes_;
};

}  // namespace ndtom
