// PointKdTree: k nearest within a radius, against a brute-force sort of all points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "ndtom/matching/point_kdtree.h"

using Eigen::Vector3d;
using ndtom::PointKdTree;

namespace {

std::vector<PointKdTree::Neighbour> bruteForce(const std::vector<Vector3d>& points,
                                               const Vector3d& q, size_t k, double max_sq) {
  std::vector<PointKdTree::Neighbour> all;
  for (uint32_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) continue;
    const double d = (points[i] - q).squaredNorm();
    if (d <= max_sq) all.push_back({i, d});
  }
  std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
    return a.squared_distance < b.squared_distance ||
           (a.squared_distance == b.squared_distance && a.index < b.index);
  });
  if (all.size() > k) all.resize(k);
  return all;
}

void expectSame(const std::vector<PointKdTree::Neighbour>& got,
                const std::vector<PointKdTree::Neighbour>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].index, want[i].index) << "rank " << i;
    EXPECT_EQ(got[i].squared_distance, want[i].squared_distance) << "rank " << i;
  }
}

}  // namespace

TEST(PointKdTree, MatchesBruteForceOnRandomClouds) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<Vector3d> points;
  for (int i = 0; i < 3000; ++i) points.emplace_back(u(rng), u(rng), 0.2 * u(rng));
  // Exact duplicates and points on a lattice make ties in distance and in split values.
  for (int i = 0; i < 200; ++i) points.push_back(points[i]);
  for (int i = 0; i < 125; ++i) points.emplace_back(i % 5, (i / 5) % 5, i / 25);
  PointKdTree tree(points);
  std::vector<PointKdTree::Neighbour> got;
  for (int trial = 0; trial < 400; ++trial) {
    const Vector3d q(u(rng), u(rng), u(rng) * 0.3);
    const size_t k = 1 + trial % 12;
    const double radius = 0.05 + 0.01 * (trial % 100);
    tree.nearest(q, k, radius * radius, got);
    expectSame(got, bruteForce(points, q, k, radius * radius));
  }
  // Lattice queries: many exactly equidistant points.
  for (int i = 0; i < 30; ++i) {
    const Vector3d q(0.5 * (i % 9), 0.5 * (i % 7), 0.5 * (i % 5));
    tree.nearest(q, 6, 4.0, got);
    expectSame(got, bruteForce(points, q, 6, 4.0));
  }
}

TEST(PointKdTree, UnboundedRadiusFindsTheKNearest) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  std::vector<Vector3d> points;
  for (int i = 0; i < 500; ++i) points.emplace_back(u(rng), u(rng), u(rng));
  PointKdTree tree(points);
  std::vector<PointKdTree::Neighbour> got;
  const double inf = std::numeric_limits<double>::infinity();
  tree.nearest(Vector3d(100, 0, 0), 5, inf, got);
  expectSame(got, bruteForce(points, Vector3d(100, 0, 0), 5, inf));
  tree.nearest(Vector3d(0, 0, 0), 1000, inf, got);  // k larger than the tree: all points
  EXPECT_EQ(got.size(), points.size());
}

TEST(PointKdTree, NonFinitePointsAreNeverReturned) {
  const double nan = std::nan("");
  std::vector<Vector3d> points = {{0, 0, 0}, {nan, 0, 0}, {1, 0, 0}, {0, INFINITY, 0}};
  PointKdTree tree(points);
  EXPECT_EQ(tree.size(), points.size());
  std::vector<PointKdTree::Neighbour> got;
  tree.nearest(Vector3d(0.1, 0, 0), 10, 100.0, got);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].index, 0u);
  EXPECT_EQ(got[1].index, 2u);
}

TEST(PointKdTree, EmptyTreeAndDegenerateQueries) {
  PointKdTree empty;
  std::vector<PointKdTree::Neighbour> got = {{1, 1.0}};
  empty.nearest(Vector3d::Zero(), 3, 1.0, got);
  EXPECT_TRUE(got.empty());
  PointKdTree empty_cloud(std::vector<Vector3d>{});
  empty_cloud.nearest(Vector3d::Zero(), 3, 1.0, got);
  EXPECT_TRUE(got.empty());

  PointKdTree tree(std::vector<Vector3d>{{0, 0, 0}, {1, 1, 1}});
  tree.nearest(Vector3d::Zero(), 0, 1.0, got);  // k = 0
  EXPECT_TRUE(got.empty());
  tree.nearest(Vector3d(std::nan(""), 0, 0), 2, 1.0, got);  // NaN query
  EXPECT_TRUE(got.empty());
  tree.nearest(Vector3d::Zero(), 2, -1.0, got);  // negative radius
  EXPECT_TRUE(got.empty());
  tree.nearest(Vector3d::Zero(), 2, 0.0, got);  // radius 0: only the coincident point
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].index, 0u);
}
