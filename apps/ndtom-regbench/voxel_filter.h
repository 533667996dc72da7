// Point decimation for the point-map peers without a filter of their own (MRPT's points map):
// the centroid of the points in each cube of a grid, as PCL's VoxelGrid does.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace ndtom::regbench {

/// One point per occupied cube of edge `leaf` (m, > 0; cube i covers [i·leaf, (i+1)·leaf)):
/// the mean of its points, in the order the cubes are first met.
std::vector<Eigen::Vector3d> voxelCentroids(const std::vector<Eigen::Vector3d>& points,
                                            double leaf);

}  // namespace ndtom::regbench
