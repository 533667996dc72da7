#include "voxel_filter.h"

#include <cmath>
#include <stdexcept>
#include <unordered_map>

namespace ndtom::regbench {

namespace {

struct Cube {
  int64_t x, y, z;
  bool operator==(const Cube& o) const { return x == o.x && y == o.y && z == o.z; }
};

struct CubeHash {
  size_t operator()(const Cube& c) const {
    return size_t(c.x * 73856093) ^ size_t(c.y * 19349669) ^ size_t(c.z * 83492791);
  }
};

}  // namespace

std::vector<Eigen::Vector3d> voxelCentroids(const std::vector<Eigen::Vector3d>& points,
                                            double leaf) {
  if (!(leaf > 0)) throw std::invalid_argument("voxelCentroids: leaf must be > 0");
  std::unordered_map<Cube, size_t, CubeHash> slot_of;
  std::vector<Eigen::Vector3d> sums;
  std::vector<double> counts;
  for (const Eigen::Vector3d& p : points) {
    const Cube cube{int64_t(std::floor(p.x() / leaf)), int64_t(std::floor(p.y() / leaf)),
                    int64_t(std::floor(p.z() / leaf))};
    const auto [it, added] = slot_of.try_emplace(cube, sums.size());
    if (added) {
      sums.push_back(Eigen::Vector3d::Zero());
      counts.push_back(0);
    }
    sums[it->second] += p;
    counts[it->second] += 1;
  }
  for (size_t i = 0; i < sums.size(); ++i) sums[i] /= counts[i];
  return sums;
}

}  // namespace ndtom::regbench
