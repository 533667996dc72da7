// The 3D DDA against brute force: every cell of the ray's bounding box tested for
// intersection with the segment, in the same half-open cell convention.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "map/ray_dda.h"
#include "support/brute_force.h"

using Eigen::Vector3d;
using ndtom::CellIndex;
using ndtom::GridGeometry;
using ndtom::testing::bruteForce;

namespace {

std::vector<CellIndex> traverse(const GridGeometry& g, const Vector3d& from, const Vector3d& to) {
  std::vector<CellIndex> cells;
  ndtom::traverseRay(g, from, to, [&](const CellIndex& c) {
    cells.push_back(c);
    return true;
  });
  return cells;
}

void expectSameAsBruteForce(const GridGeometry& g, const Vector3d& from, const Vector3d& to) {
  const auto visited = traverse(g, from, to);
  const std::set<CellIndex> unique(visited.begin(), visited.end());
  ASSERT_EQ(unique.size(), visited.size()) << "a cell was visited twice";
  for (size_t i = 1; i < visited.size(); ++i)
    for (int a = 0; a < 3; ++a)
      ASSERT_LE(std::abs(visited[i][a] - visited[i - 1][a]), 1) << "cells not adjacent";
  const auto expected = bruteForce(g, from, to);
  ASSERT_EQ(unique, expected) << "from " << from.transpose() << " to " << to.transpose()
                              << " at resolution " << g.resolution();
}

std::vector<CellIndex> cells(std::initializer_list<CellIndex> list) {
  return list;
}

}  // namespace

TEST(RayDda, HandCheckedCases) {
  const GridGeometry g(1.0);
  // Diagonal through an edge: the side cells are never touched.
  EXPECT_EQ(traverse(g, {0.5, 0.5, 0.5}, {2.5, 2.5, 0.5}), cells({{0, 0, 0}, {1, 1, 0}}));
  // Up in x, down in y through an edge: at the crossing the point (1, 2) lies in cell (1, 2).
  EXPECT_EQ(traverse(g, {0.5, 2.5, 0.5}, {2.5, 0.5, 0.5}),
            cells({{0, 2, 0}, {1, 2, 0}, {1, 1, 0}, {2, 1, 0}}));
  // Endpoint on a face: it belongs to the upper cell, which holds the hit.
  EXPECT_EQ(traverse(g, {0.5, 0.5, 0.5}, {2.0, 0.5, 0.5}), cells({{0, 0, 0}, {1, 0, 0}}));
  EXPECT_EQ(traverse(g, {2.5, 0.5, 0.5}, {1.0, 0.5, 0.5}), cells({{2, 0, 0}}));
  // Negative coordinates use floor, not truncation.
  EXPECT_EQ(traverse(g, {-0.5, 0.5, 0.5}, {-2.5, 0.5, 0.5}), cells({{-1, 0, 0}, {-2, 0, 0}}));
  // A ray inside one cell crosses nothing.
  EXPECT_TRUE(traverse(g, {0.1, 0.1, 0.1}, {0.9, 0.9, 0.9}).empty());
}

TEST(RayDda, RandomRaysMatchBruteForce) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> coord(-3.0, 3.0);
  const double resolutions[] = {0.1, 0.2, 0.37, 1.0};
  for (int i = 0; i < 10000; ++i) {
    const GridGeometry g(resolutions[i % 4]);
    const Vector3d from(coord(rng), coord(rng), coord(rng));
    const Vector3d to(coord(rng), coord(rng), coord(rng));
    expectSameAsBruteForce(g, from, to);
    if (HasFatalFailure()) return;
  }
}

TEST(RayDda, AxisParallelRaysMatchBruteForce) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> coord(-2.0, 2.0);
  for (int i = 0; i < 3000; ++i) {
    const GridGeometry g(i % 2 ? 0.25 : 0.3);
    const Vector3d from(coord(rng), coord(rng), coord(rng));
    Vector3d to = from;
    to[i % 3] = coord(rng);                        // moves along one axis
    if (i % 5 == 0) to[(i + 1) % 3] = coord(rng);  // or in an axis-parallel plane
    expectSameAsBruteForce(g, from, to);
    if (HasFatalFailure()) return;
  }
}

// Rays through cell edges and corners, and endpoints on faces, built from dyadic numbers so
// that the crossing times tie exactly in floating point.
TEST(RayDda, RaysThroughCornersAndFacesMatchBruteForce) {
  std::mt19937 rng(11);
  const double steps[] = {-2, -1, -0.5, 0, 0.5, 1, 2};
  const double spans[] = {0.25, 0.5, 1, 1.5, 2, 3};
  const double resolutions[] = {0.25, 0.5, 1.0};
  std::uniform_int_distribution<int> pick_step(0, 6), pick_span(0, 5), pick_corner(-4, 4);
  int tested = 0;
  for (int i = 0; tested < 3000; ++i) {
    const GridGeometry g(resolutions[i % 3]);
    const Vector3d direction(steps[pick_step(rng)], steps[pick_step(rng)], steps[pick_step(rng)]);
    if (direction.isZero()) continue;
    const Vector3d corner =
        g.resolution() * Vector3d(pick_corner(rng), pick_corner(rng), pick_corner(rng));
    const Vector3d from = corner - spans[pick_span(rng)] * direction;
    // Half of the rays end exactly on the corner (on faces, edges or the corner itself).
    const Vector3d to = (i % 2) ? corner : Vector3d(corner + spans[pick_span(rng)] * direction);
    expectSameAsBruteForce(g, from, to);
    if (HasFatalFailure()) return;
    ++tested;
  }
}

namespace {

// Records every visit with the ray it belongs to (set per ray by walkRays' callback).
struct RecordingWalker {
  std::vector<std::pair<int, CellIndex>>* visits;
  int ray = -1;
  CellIndex cell;
  void start(const CellIndex& first) { cell = first; }
  template <int Axis>
  void move(int32_t step) {
    cell[Axis] += step;
  }
  bool visit() {
    visits->push_back({ray, cell});
    return true;
  }
};

}  // namespace

// Many rays in one call (the walker kept in registers from ray to ray) visit what one call
// per ray visits, in the same order; skipped rays visit nothing.
TEST(RayDda, WalkRaysMatchesOneWalkPerRay) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> coord(-4.0, 4.0);
  const GridGeometry g(0.3);
  const Vector3d origin(0.1, -0.2, 0.05);
  std::vector<Vector3d> ends(500);
  for (Vector3d& e : ends) e = Vector3d(coord(rng), coord(rng), coord(rng));
  auto skipped = [](size_t i) { return i % 7 == 3; };

  std::vector<std::pair<int, CellIndex>> expected, actual;
  for (size_t i = 40; i < 460; ++i) {
    if (skipped(i)) continue;
    ndtom::walkRay(g, origin, ends[i], RecordingWalker{&expected, int(i), {}});
  }
  const RecordingWalker last = ndtom::walkRays(
      g, origin, 40, 460,
      [&](size_t i, RecordingWalker& w) -> const Vector3d* {
        if (skipped(i)) return nullptr;
        w.ray = int(i);
        return &ends[i];
      },
      RecordingWalker{&actual, -1, {}});
  EXPECT_GT(expected.size(), 1000u);
  EXPECT_EQ(actual, expected);
  EXPECT_EQ(last.ray, 459);  // the walker's state comes back to the caller
}
