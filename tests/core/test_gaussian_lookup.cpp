// GaussianLookup: the same Gaussians as the map, with inverses and projections checked
// against a direct matrix inverse (not the eigen decomposition the lookup uses).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <random>
#include <map>
#include <set>

#include "ndtom/matching/gaussian_lookup.h"
#include "synthetic_room.h"

using Eigen::Matrix3d;
using Eigen::Vector3d;
using ndtom::GaussianLookup;
using ndtom::NdtMap;
using ndtom::PreparedGaussian;

namespace {

NdtMap roomMap(double resolution) {
  return ndtom::testing::roomMap(resolution, 40000);
}

}  // namespace

std::vector<const PreparedGaussian*> gaussiansOf(const GaussianLookup& lookup) {
  std::vector<const PreparedGaussian*> out;
  lookup.forEachGaussian([&](const PreparedGaussian& g) { out.push_back(&g); });
  return out;
}

/// `got` holds `want`'s Gaussians in the same order, each found by its cell.
void expectSameGaussians(const GaussianLookup& got_lookup, const GaussianLookup& want_lookup) {
  ASSERT_EQ(got_lookup.size(), want_lookup.size());
  const auto got = gaussiansOf(got_lookup), want = gaussiansOf(want_lookup);
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i]->cell, want[i]->cell);
    EXPECT_EQ(got[i]->mean, want[i]->mean);
    EXPECT_EQ(got[i]->information, want[i]->information);
    EXPECT_EQ(got_lookup.find(got[i]->cell), got[i]);
  }
}

TEST(GaussianLookup, HoldsEveryGaussianOfTheMapInBlockOrder) {
  const NdtMap map = roomMap(0.5);
  const GaussianLookup lookup(map);
  ASSERT_GT(lookup.size(), 100u);
  EXPECT_EQ(lookup.size(), map.numGaussians());
  const auto gaussians = gaussiansOf(lookup);
  ASSERT_EQ(gaussians.size(), lookup.size());
  for (size_t i = 1; i < gaussians.size(); ++i) {
    const ndtom::CellIndex a = gaussians[i - 1]->cell, b = gaussians[i]->cell;
    EXPECT_TRUE(ndtom::blockOf(a) < ndtom::blockOf(b) ||
                (ndtom::blockOf(a) == ndtom::blockOf(b) &&
                 ndtom::offsetInBlock(a) < ndtom::offsetInBlock(b)));
  }
  EXPECT_EQ(lookup.means().size(), lookup.size());
  for (uint32_t i = 0; i < gaussians.size(); ++i) EXPECT_EQ(&lookup.meanOwner(i), gaussians[i]);

  for (const PreparedGaussian* owned : gaussians) {
    const PreparedGaussian& g = *owned;
    const auto expected = map.gaussian(g.cell, ndtom::Covariance::Regularized);
    ASSERT_TRUE(expected.has_value());
    EXPECT_EQ(g.n, expected->n);
    EXPECT_EQ(g.mean, expected->mean);
    EXPECT_EQ(lookup.find(g.cell), &g);
    EXPECT_EQ(lookup.findAt(g.mean), &g) << "a cell's mean lies inside the cell";

    const Matrix3d inverse = expected->covariance.inverse();
    EXPECT_LT((g.information - inverse).norm(), 1e-9 * inverse.norm());
    const double lambda_min =
        expected->covariance.selfadjointView<Eigen::Lower>().eigenvalues().minCoeff();
    const Matrix3d projection = lambda_min * inverse;
    EXPECT_LT((g.projection - projection).norm(), 1e-9);
  }
}

TEST(GaussianLookup, CellsWithoutGaussianAreNotFound) {
  const NdtMap map = roomMap(0.5);
  const GaussianLookup lookup(map);
  size_t checked = 0;
  map.forEachCell([&](const ndtom::CellView& c) {
    const bool has = c.stats && c.stats->hasGaussian();
    EXPECT_EQ(lookup.find(c.index) != nullptr, has);
    ++checked;
  });
  EXPECT_GT(checked, lookup.size()) << "free cells exist too";
  EXPECT_EQ(lookup.find({100000, 0, 0}), nullptr);
  EXPECT_EQ(lookup.findAt(Vector3d(std::nan(""), 0, 0)), nullptr);
  EXPECT_EQ(lookup.findAt(Vector3d(1e300, 0, 0)), nullptr);
}

TEST(GaussianLookup, ProjectionMovesAPointOntoAPlanarCellsPlane) {
  // Points on the plane z = 0.05 inside one cell: the projection keeps x, y and sets z.
  ndtom::MapOptions options;
  options.resolution = 1.0;
  NdtMap map(options);
  std::vector<Vector3d> points;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) points.emplace_back(0.05 + 0.1 * i, 0.05 + 0.1 * j, 0.05);
  map.insertScan(points, Vector3d(0.5, 0.5, 3.0));
  const GaussianLookup lookup(map);
  ASSERT_EQ(lookup.size(), 1u);
  const auto& g = *gaussiansOf(lookup)[0];
  const Vector3d p(0.3, 0.7, 0.4);
  const Vector3d foot = p - g.projection * (p - g.mean);
  EXPECT_NEAR(foot.z(), 0.05, 1e-12);
  // In-plane offsets shrink by λ_min/λ = the regularisation ratio (0.01 by default).
  EXPECT_NEAR(foot.x(), p.x() - 0.01 * (p.x() - g.mean.x()), 1e-9);
  EXPECT_NEAR(foot.y(), p.y() - 0.01 * (p.y() - g.mean.y()), 1e-9);
}

TEST(GaussianLookup, SingularCovarianceStillHasAFiniteInverse) {
  // Regularisation switched off and collinear points: the covariance has rank 1.
  ndtom::MapOptions options;
  options.resolution = 1.0;
  options.regularization.min_eigen_ratio = 0;
  options.regularization.min_eigen_abs = 0;
  NdtMap map(options);
  map.insertScan({{0.1, 0.5, 0.5}, {0.5, 0.5, 0.5}, {0.9, 0.5, 0.5}}, Vector3d(0.5, 0.5, 5));
  const GaussianLookup lookup(map);
  ASSERT_EQ(lookup.size(), 1u);
  EXPECT_TRUE(gaussiansOf(lookup)[0]->information.allFinite());
  EXPECT_TRUE(gaussiansOf(lookup)[0]->projection.allFinite());
}

TEST(GaussianLookup, EmptyMap) {
  const GaussianLookup lookup{NdtMap{}};
  EXPECT_TRUE(lookup.empty());
  EXPECT_EQ(lookup.findAt(Vector3d::Zero()), nullptr);
}

TEST(GaussianLookup, ForEachAroundVisitsExactlyTheNeighbourCellsGaussians) {
  // Every cell of a 20³ region around the origin (negative indices, block edges) holds a
  // Gaussian or not at random; the 27-cell walk must agree with 27 single lookups.
  ndtom::MapOptions options;
  options.resolution = 1.0;
  options.occupancy.enabled = false;
  NdtMap map(options);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  std::vector<Vector3d> points;
  for (int x = -10; x < 10; ++x)
    for (int y = -10; y < 10; ++y)
      for (int z = -10; z < 10; ++z)
        if (rng() % 3 == 0)
          for (int k = 0; k < 4; ++k) points.emplace_back(x + u(rng), y + u(rng), z + u(rng));
  map.insertScan(points, Vector3d(0.5, 0.5, 0.5));
  const GaussianLookup lookup(map);
  ASSERT_GT(lookup.size(), 1000u);
  for (int x = -11; x <= 10; ++x)
    for (int y = -11; y <= 10; y += 3)
      for (int z = -11; z <= 10; z += 4) {
        std::set<const ndtom::PreparedGaussian*> walked, expected;
        lookup.forEachAround({x, y, z}, [&](const ndtom::PreparedGaussian& g) {
          EXPECT_TRUE(walked.insert(&g).second) << "visited twice";
        });
        for (int dx = -1; dx <= 1; ++dx)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz)
              if (const auto* g = lookup.find({x + dx, y + dy, z + dz})) expected.insert(g);
        EXPECT_EQ(walked, expected) << x << "," << y << "," << z;
      }
}

// Issue #38: the index took 2 KB per block, so a map of one Gaussian a block (and each
// pyramid level over it) cost 2 KB a Gaussian. Now a bit per cell and its rank below 32
// Gaussians a block, an index per cell from 32: a full block, blocks of 31 and 32 spread over
// every word of the mask, and scattered blocks are all found exactly, in a few hundred bytes
// a Gaussian.
TEST(GaussianLookup, SparseAndFullBlocksAreIndexedByRank) {
  ndtom::MapOptions o;
  o.resolution = 0.5;
  o.occupancy.enabled = false;
  NdtMap map(o);
  ndtom::CellStats stats;
  stats.n = 3;
  stats.scatter = Matrix3d::Identity() * 0.01;
  std::set<ndtom::CellIndex> cells;
  for (int i = 0; i < 8; ++i)  // block (0, 0, 0), every cell
    for (int j = 0; j < 8; ++j)
      for (int k = 0; k < 8; ++k) cells.insert({i, j, k});
  for (const int count : {31, 32})  // blocks of a few dozen Gaussians, every mask word
    for (int k = 0; k < count; ++k) cells.insert({8 * count + k % 8, (3 * k) % 8, k / 4});
  std::mt19937 rng(4);
  std::uniform_int_distribution<int> block(-200, 200), offset(0, 7);
  while (cells.size() < 512 + 63 + 3000)  // one cell in each of 3000 other blocks
    cells.insert({16 * block(rng) + offset(rng) + 8, 8 * block(rng) + offset(rng),
                  8 * (block(rng) % 4) + offset(rng)});
  for (const auto& c : cells) map.setCell(c, 0.f, stats);
  const GaussianLookup lookup(map);
  ASSERT_EQ(lookup.size(), cells.size());
  for (const auto& c : cells) {
    const auto* g = lookup.find(c);
    ASSERT_NE(g, nullptr);
    EXPECT_EQ(g->cell, c);
  }
  for (int i = 0; i < 2000; ++i) {  // random cells: found exactly when they hold a Gaussian
    const ndtom::CellIndex c{16 * block(rng) + offset(rng) + 8, 8 * block(rng) + offset(rng),
                             8 * (block(rng) % 4) + offset(rng)};
    EXPECT_EQ(lookup.find(c) != nullptr, cells.count(c) > 0);
  }
  EXPECT_LE(lookup.memoryBytes(), cells.size() * GaussianLookup::maxBytesPerGaussian() +
                                      map.numBlocks() * 2 * sizeof(void*));
  EXPECT_LT(GaussianLookup::maxBytesPerGaussian(), 512u);
}

TEST(GaussianLookup, UpdateGivesTheLookupOfTheChangedSet) {
  // Two maps' Gaussians on one grid: the lookup of the first, updated to drop some cells,
  // change others and add new ones, against a lookup built from the resulting set.
  const NdtMap a = roomMap(0.5);
  const NdtMap b = ndtom::testing::roomMap(0.5, 20000);
  std::vector<ndtom::Gaussian> first, second;
  a.forEachGaussian([&](const ndtom::Gaussian& g) { first.push_back(g); });
  b.forEachGaussian([&](const ndtom::Gaussian& g) { second.push_back(g); });
  ASSERT_GT(first.size(), 100u);
  const ndtom::LookupOptions no_tree{false, false};
  GaussianLookup lookup(a.geometry(), first, no_tree);
  std::map<ndtom::CellIndex, ndtom::Gaussian> expected;
  for (const auto& g : first) expected[g.cell] = g;
  std::vector<ndtom::CellChange> changes;
  for (size_t i = 0; i < first.size(); i += 3) {  // a third of the cells lose their Gaussian
    changes.push_back({first[i].cell, std::nullopt});
    expected.erase(first[i].cell);
  }
  for (size_t i = 0; i < second.size(); i += 2) {  // half of b's replace or join
    if (expected.count(second[i].cell) == 0 &&
        std::any_of(changes.begin(), changes.end(),
                    [&](const auto& c) { return c.cell == second[i].cell; }))
      continue;  // one change per cell
    changes.push_back({second[i].cell, ndtom::prepared(second[i])});
    expected[second[i].cell] = second[i];
  }
  changes.push_back({{1000, 1000, 1000}, std::nullopt});  // a cell that never had one
  lookup.update(changes);
  std::vector<ndtom::Gaussian> remaining;
  for (const auto& [cell, g] : expected) remaining.push_back(g);
  const GaussianLookup rebuilt(a.geometry(), remaining, no_tree);
  expectSameGaussians(lookup, rebuilt);
  for (size_t i = 0; i < first.size(); i += 3) {
    if (expected.count(first[i].cell) == 0) {
      EXPECT_EQ(lookup.find(first[i].cell), nullptr);
    }
  }
  GaussianLookup with_tree(a.geometry(), first);
  EXPECT_THROW(with_tree.update({}), std::logic_error) << "its k-d tree would go stale";
}

TEST(GaussianLookup, BlocksMadeElsewhereGiveTheLookupOfTheirGaussians) {
  // The map's Gaussians grouped into blocks by hand (a std::map keyed by block, then
  // offset), against the lookup of the same Gaussians given in any order.
  const NdtMap map = roomMap(0.5);
  std::map<ndtom::CellIndex, std::map<int, ndtom::Gaussian>> by_block;
  std::vector<ndtom::Gaussian> all;
  map.forEachGaussian([&](const ndtom::Gaussian& g) {
    by_block[ndtom::blockOf(g.cell)][ndtom::offsetInBlock(g.cell)] = g;
    all.push_back(g);
  });
  ASSERT_GT(by_block.size(), 3u);
  std::vector<ndtom::GaussianBlock> blocks;
  blocks.push_back({{-100000, 0, 0}, {}, {}});  // empty: skipped
  for (const auto& [key, cells] : by_block) {
    ndtom::GaussianBlock b;
    b.block = key;
    for (const auto& [offset, g] : cells) {
      b.cells[size_t(offset) / 64] |= uint64_t(1) << (offset % 64);
      b.gaussians.push_back(ndtom::prepared(g));
    }
    blocks.push_back(std::move(b));
  }
  blocks.push_back({{100000, 0, 0}, {}, {}});
  const GaussianLookup from_blocks(map.geometry(), blocks);
  const GaussianLookup from_any_order(map.geometry(), all);
  ASSERT_EQ(from_blocks.size(), all.size());
  expectSameGaussians(from_blocks, from_any_order);
  const auto got = gaussiansOf(from_blocks);
  for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(&from_blocks.meanOwner(uint32_t(i)), got[i]);
  EXPECT_EQ(from_blocks.memoryBytes(), from_any_order.memoryBytes());
  EXPECT_EQ(from_blocks.find({1000, 1000, 1000}), nullptr);

  auto swapped = blocks;
  std::swap(swapped[1], swapped[2]);
  EXPECT_THROW(GaussianLookup(map.geometry(), swapped), std::invalid_argument);
  auto miscounted = blocks;
  miscounted[1].gaussians.pop_back();
  EXPECT_THROW(GaussianLookup(map.geometry(), miscounted), std::invalid_argument);
}
