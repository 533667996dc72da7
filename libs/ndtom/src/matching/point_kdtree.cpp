#include "ndtom/matching/point_kdtree.h"

#include <algorithm>

namespace ndtom {
namespace {

bool closer(const PointKdTree::Neighbour& a, const PointKdTree::Neighbour& b) {
  return a.squared_distance < b.squared_distance ||
         (a.squared_distance == b.squared_distance && a.index < b.index);
}

}  // namespace

PointKdTree::PointKdTree(const std::vector<Eigen::Vector3d>& points) : points_(points) {
  order_.reserve(points_.size());
  for (uint32_t i = 0; i < points_.size(); ++i)
    if (points_[i].allFinite()) order_.push_back(i);
  if (!order_.empty()) {
    nodes_.reserve(2 * order_.size() / kLeafSize + 1);
    build(0, uint32_t(order_.size()));
  }
}

uint32_t PointKdTree::build(uint32_t begin, uint32_t end) {
  const uint32_t id = uint32_t(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= kLeafSize) {
    nodes_[id].begin = begin;
    nodes_[id].end = end;
    return id;
  }
  // Split the widest extent at the median: balanced, so the depth is log2(n / kLeafSize).
  Eigen::Vector3d lo = points_[order_[begin]], hi = lo;
  for (uint32_t i = begin; i < end; ++i) {
    lo = lo.cwiseMin(points_[order_[i]]);
    hi = hi.cwiseMax(points_[order_[i]]);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](uint32_t a, uint32_t b) { return points_[a][axis] < points_[b][axis]; });
  const double split = points_[order_[mid]][axis];
  const uint32_t left = build(begin, mid);
  const uint32_t right = build(mid, end);
  Node& node = nodes_[id];  // after the recursion: nodes_ may have grown
  node.axis = axis;
  node.split = split;
  node.left = left;
  node.right = right;
  return id;
}

void PointKdTree::nearest(const Eigen::Vector3d& query, size_t k, double max_squared_distance,
                          std::vector<Neighbour>& out) const {
  out.clear();
  if (nodes_.empty() || k == 0 || !query.allFinite() || !(max_squared_distance >= 0)) return;
  double bound = max_squared_distance;
  search(0, query, k, bound, out);
}

void PointKdTree::search(uint32_t id, const Eigen::Vector3d& query, size_t k, double& bound,
                         std::vector<Neighbour>& out) const {
  const Node& node = nodes_[id];
  if (node.axis < 0) {
    for (uint32_t i = node.begin; i < node.end; ++i) {
      const Neighbour candidate{order_[i], (points_[order_[i]] - query).squaredNorm()};
      if (candidate.squared_distance > bound) continue;
      if (out.size() == k) {
        if (!closer(candidate, out.back())) continue;
        out.pop_back();
      }
      out.insert(std::upper_bound(out.begin(), out.end(), candidate, closer), candidate);
      if (out.size() == k) bound = out.back().squared_distance;
    }
    return;
  }
  const double diff = query[node.axis] - node.split;
  const uint32_t near_child = diff <= 0 ? node.left : node.right;
  const uint32_t far_child = diff <= 0 ? node.right : node.left;
  search(near_child, query, k, bound, out);
  if (diff * diff <= bound) search(far_child, query, k, bound, out);
}

}  // namespace ndtom
