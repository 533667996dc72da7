#pragma once
// Which of a scan's points each process of a distributed build classifies and walks, when
// the processes share the rays out: contiguous shares of about equal work. Equal counts of
// points are not equal work: a lidar's fan towards a wall 30 m off takes several times the
// cells of one towards a wall 5 m off.
#include <Eigen/Core>
#include <cstddef>
#include <utility>

#include "insertion/scan_context.h"

namespace ndtom {

/// Work of a point's ray, in cell visits: the cells a ray crosses (its L1 length, truncated
/// at max_range, over the resolution) plus what a point costs besides its walk.
double pointWork(const ScanContext& scan, const Eigen::Vector3d& point);

/// [first, last) of process `rank` of `ranks`. The shares cover the points in order and have
/// about equal pointWork, estimated from every kShareStride-th point, so every process
/// computes every share alike (the same points, the same sums) at a small cost.
std::pair<size_t, size_t> pointShare(const ScanContext& scan, const Eigen::Vector3d* points,
                                     size_t n, size_t ranks, size_t rank);

inline constexpr size_t kShareStride = 32;

}  // namespace ndtom
