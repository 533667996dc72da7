// ndtom-localize's pieces: the constant-velocity prediction against trajectories whose
// motion is known, the --initial pose parser, the resident tiles of a region map against
// the rule computed from the tiles' coordinates, and the live map beside the prior one.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "live_map.h"
#include "localize_options.h"
#include "mapper/mapper_run.h"
#include "ndtom/files/tiled_map_io.h"
#include "ndtom/localization/motion_prediction.h"
#include "ndtom/map/block_grid.h"
#include "ndtom_apps/option_values.h"
#include "region_map.h"

using namespace ndtom::localizer;
using Eigen::Isometry3d;
using Eigen::Vector3d;
using ndtom::ConstantVelocity;
using ndtom::scaledMotion;

namespace {

Isometry3d motionOf(const Vector3d& t, double angle, const Vector3d& axis) {
  Isometry3d m = Isometry3d::Identity();
  m.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  m.translation() = t;
  return m;
}

// A flat map of 0.4 m cells over [0, 3.2·side)² m (96 m): in each 3.2 m block of the ground, 1 to
// 30 free cells (so that tiles differ in bytes) and, in one block in three, a Gaussian.
ndtom::NdtMap groundMap(int side = 30) {
  ndtom::MapOptions o;
  o.resolution = 0.4;
  ndtom::NdtMap map(o);
  ndtom::CellStats gaussian;
  gaussian.n = 5;
  gaussian.scatter = Eigen::Matrix3d::Identity() * 0.01;
  for (int bx = 0; bx < side; ++bx)
    for (int by = 0; by < side; ++by) {
      const int cells = 1 + (bx * 7 + by * 13) % 30;
      for (int i = 0; i < cells; ++i)
        map.setCell({bx * 8 + i % 8, by * 8 + i / 8, 0}, -0.5f, ndtom::CellStats{});
      if ((bx + by) % 3 == 0) map.setCell({bx * 8 + 7, by * 8 + 7, 0}, 2.f, gaussian);
    }
  map.shrinkToFit();
  return map;
}

}  // namespace

// The rule, computed from tile coordinates (tiles of 2 blocks: 6.4 m): a tile is resident if
// within the radius (x-y) of the position, or resident before and within radius + 6.4 m.
// Driven twice round a loop, the region holds exactly those tiles' cells, and the second
// round, where the robot has been before, takes the memory the first took at each place.
TEST(RegionMap, HoldsTheTilesWithinTheRadiusAndNoMoreOnASecondRound) {
  const mapper_test::TempDir dir;
  const ndtom::NdtMap whole = groundMap();
  const std::string path = (dir / "ground.ndtomtiles").string();
  ndtom::saveTiledMap(whole, path, 2);
  const double edge = 6.4, radius = 15;
  std::map<std::pair<int, int>, size_t> cells_of_tile;  // from the cells, not the file
  whole.forEachCell([&](const ndtom::CellView& c) {
    ++cells_of_tile[{int(std::floor(c.index.x / 16.0)), int(std::floor(c.index.y / 16.0))}];
  });
  const auto distance = [&](std::pair<int, int> t, const Vector3d& p) {
    const double dx = std::max({t.first * edge - p.x(), 0.0, p.x() - (t.first + 1) * edge});
    const double dy = std::max({t.second * edge - p.y(), 0.0, p.y() - (t.second + 1) * edge});
    return std::hypot(dx, dy);
  };
  std::vector<Vector3d> loop;  // a square of side 60 m from (18, 18), every 2 m
  for (int i = 0; i < 120; ++i) {
    const double s = 2.0 * (i % 30), side = i / 30;
    const Vector3d corner[4] = {{18, 18, 1}, {78, 18, 1}, {78, 78, 1}, {18, 78, 1}};
    const Vector3d along[4] = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
    loop.push_back(corner[int(side)] + s * along[int(side)]);
  }
  ndtom::localizer::RegionMap region(path, radius);
  std::set<std::pair<int, int>> expected;
  std::vector<size_t> first_round_bytes;
  std::vector<std::set<std::pair<int, int>>> first_round_tiles;
  size_t compared = 0;
  for (int round = 0; round < 2; ++round)
    for (size_t i = 0; i < loop.size(); ++i) {
      region.keepAround(loop[i]);
      std::set<std::pair<int, int>> next;
      for (const auto& [tile, cells] : cells_of_tile)
        if (distance(tile, loop[i]) <= radius ||
            (expected.count(tile) && distance(tile, loop[i]) <= radius + edge))
          next.insert(tile);
      expected.swap(next);
      size_t cells = 0;
      for (const auto& t : expected) cells += cells_of_tile[t];
      ASSERT_EQ(region.residentTiles(), expected.size()) << round << " " << i;
      ASSERT_EQ(region.map().numCells(), cells) << round << " " << i;
      region.map().forEachBlock([&](const ndtom::CellIndex& b) {
        ASSERT_TRUE(expected.count({int(std::floor(b.x / 2.0)), int(std::floor(b.y / 2.0))}))
            << round << " " << i << ": block " << b.x << " " << b.y;
      });
      // Where the same tiles are resident (not at the start: the first round began with
      // none), the same bytes; the hash table's buckets may differ with its history.
      if (round == 0) {
        first_round_bytes.push_back(region.map().memoryBytes());
        first_round_tiles.push_back(expected);
      } else if (expected == first_round_tiles[i]) {
        ++compared;
        EXPECT_NEAR(double(region.map().memoryBytes()), double(first_round_bytes[i]),
                    0.02 * double(first_round_bytes[i]))
            << i;
      }
    }
  EXPECT_GT(compared, loop.size() / 2);
  EXPECT_GT(region.drops(), 0u);
  EXPECT_LT(region.residentTiles(), cells_of_tile.size());
}

TEST(MotionPrediction, ConstantVelocityContinuesAConstantMotion) {
  // A robot repeating one motion every 0.5 s is predicted exactly; with a step of 1 s the
  // prediction is the motion applied twice (the same screw, twice as far).
  const Isometry3d step = motionOf(Vector3d(0.4, 0.1, 0.02), 0.1, Vector3d(0.1, 0.2, 1));
  Isometry3d pose = motionOf(Vector3d(5, -2, 1), 0.3, Vector3d::UnitZ());
  ConstantVelocity cv(pose);
  EXPECT_TRUE(cv.predict(0).isApprox(pose));
  double t = 10;
  for (int k = 0; k < 5; ++k) {
    cv.update(pose, t);
    pose = pose * step;
    t += 0.5;
    if (k >= 1) {
      EXPECT_TRUE(cv.predict(t).isApprox(pose, 1e-12)) << k;
    }
  }
  EXPECT_TRUE(cv.predict(t + 0.5).isApprox(pose * step, 1e-12));
  EXPECT_TRUE(cv.lastPose().isApprox(pose * step.inverse()));
}

TEST(MotionPrediction, ScaledMotionIsAFractionOfTheScrew) {
  const Isometry3d m = motionOf(Vector3d(0.3, -0.2, 0.1), 0.2, Vector3d(0, 0, 1));
  EXPECT_TRUE(scaledMotion(m, 1).isApprox(m));
  EXPECT_TRUE(scaledMotion(m, 0).isApprox(Isometry3d::Identity()));
  const Isometry3d half = scaledMotion(m, 0.5);
  EXPECT_NEAR(Eigen::AngleAxisd(half.linear()).angle(), 0.1, 1e-12);
  EXPECT_TRUE((half * half).isApprox(m, 1e-12));
  EXPECT_TRUE(scaledMotion(m, 3).isApprox(m * m * m, 1e-12));
  EXPECT_TRUE(scaledMotion(m, -1).isApprox(m.inverse(), 1e-12));
}

TEST(LocalizeOptions, InitialPoseInTumOrder) {
  const Isometry3d p = parsePose("--initial", "1 2 3 0 0 0.7071067811865476 0.7071067811865476");
  EXPECT_TRUE(p.translation().isApprox(Vector3d(1, 2, 3)));
  EXPECT_TRUE((p.linear() * Vector3d::UnitX()).isApprox(Vector3d::UnitY(), 1e-12));
  for (const char* bad :
       {"1 2 3", "1 2 3 0 0 0 0", "1 2 3 0 0 0 x", "1 2 3 0 0 0 1 5", "nan 0 0 0 0 0 1"})
    EXPECT_THROW(parsePose("--initial", bad), ndtom::apps::UsageError) << bad;
}

namespace {

// A wall of points along y at x = `x`, from y0 to y1, seen from (x - 5, mid, 1).
std::vector<Vector3d> wallScan(double x, double y0, double y1) {
  std::vector<Vector3d> points;
  for (double y = y0; y < y1; y += 0.05)
    for (double z = 0.05; z < 3; z += 0.05) points.emplace_back(x, y, z);
  return points;
}

}  // namespace

// The target is the prior map's region with the live map's cells where the prior has none,
// or has no Gaussian where the live map has one: every prior Gaussian as it is. The extended
// map is the prior map plus the live cells it lacks, and blocks far behind the robot leave
// the live map.
TEST(LiveMap, PriorGaussiansWinAndLiveCellsFillTheRest) {
  ndtom::MapOptions o;
  o.resolution = 0.2;
  ndtom::NdtMap prior(o);
  prior.insertScan(wallScan(10, -10, 0), Vector3d(5, -5, 1));
  LiveMapSettings settings;
  settings.radius = 40;
  settings.keep_all = true;
  LiveMap live(o, settings);
  live.insert(wallScan(10.02, -6, 12), Vector3d(5, 3, 1));  // overlaps the prior's wall
  live.insert(wallScan(8, -8, -2), Vector3d(5, -5, 1));     // where the prior saw free space
  Isometry3d at = Isometry3d::Identity();
  at.translation() = Vector3d(5, 0, 1);
  const ndtom::NdtMap& target = live.targetAround(prior, at);
  const auto gaussian = [](const std::optional<ndtom::CellView>& c) {
    return c && c->stats && c->stats->hasGaussian();
  };
  size_t from_live = 0, live_over_prior = 0;
  target.forEachCell([&](const ndtom::CellView& c) {
    const auto p = prior.cell(c.index), l = live.map().cell(c.index);
    if (p && (gaussian(p) || !gaussian(l))) {  // the prior's, as it is
      EXPECT_EQ(c.logodds, p->logodds);
      EXPECT_EQ(gaussian(c), gaussian(p));
      return;
    }
    ASSERT_TRUE(l.has_value());  // else the live map's
    EXPECT_EQ(c.logodds, l->logodds);
    ++from_live;
    live_over_prior += p.has_value();
  });
  EXPECT_GT(live_over_prior, 0u);  // a live Gaussian where the prior saw only free space
  EXPECT_GT(from_live, 100u);
  prior.forEachCell([&](const ndtom::CellView& c) { EXPECT_TRUE(target.cell(c.index)); });
  // Unchanged map, unchanged policy: the same target object, not cut again.
  EXPECT_EQ(&live.targetAround(prior, at), &target);

  const ndtom::NdtMap extended = live.extended(prior);
  EXPECT_GT(extended.numCells(), prior.numCells());
  prior.forEachCell([&](const ndtom::CellView& c) {
    const auto e = extended.cell(c.index);
    ASSERT_TRUE(e.has_value());
    EXPECT_EQ(e->logodds, c.logodds);
  });

  // 500 m on, the first wall is far behind: it leaves the live map, but stays in the extended
  // map (kept for --save-map).
  const size_t before = live.map().numCells();
  live.insert(wallScan(510, 0, 5), Vector3d(505, 2, 1));
  EXPECT_LT(live.map().numCells(), before);
  EXPECT_FALSE(live.map().cellAt(Vector3d(10.02, 5.0, 1.0)).has_value());
  EXPECT_TRUE(live.extended(prior).cellAt(Vector3d(10.02, 5.0, 1.0)).has_value());
}

// Issue #38: tiles far from the robot were dropped one by one, each a walk over every
// resident block (20k tiles: 27 s a scan). Dropped all at once, the region holds exactly the
// tiles of the rule; and a tile that would take the region past its memory budget is
// refused naming the file and the tile.
TEST(RegionMap, ManyTilesDroppedAtOnceAndTheBudgetNamesTheTile) {
  const mapper_test::TempDir dir;
  const ndtom::NdtMap whole = groundMap();
  const std::string path = (dir / "ground-1.ndtomtiles").string();
  ndtom::saveTiledMap(whole, path, 1);  // 900 tiles of one block (3.2 m)
  ndtom::localizer::RegionMap region(path, 10);
  region.keepEverything();
  ASSERT_EQ(region.map().numCells(), whole.numCells());
  const Vector3d p(50, 50, 1);
  region.keepAround(p);  // drops hundreds of tiles at once
  size_t cells = 0, tiles = 0;
  std::set<ndtom::CellIndex> kept;
  for (const ndtom::TileInfo& t : region.file().tiles()) {
    const Eigen::AlignedBox3d box = region.file().tileBox(t.tile);
    const double dx = std::max({box.min().x() - p.x(), 0.0, p.x() - box.max().x()});
    const double dy = std::max({box.min().y() - p.y(), 0.0, p.y() - box.max().y()});
    if (std::hypot(dx, dy) > 10 + 3.2) continue;  // kept: within the radius + a tile's edge
    cells += t.cells;
    ++tiles;
    kept.insert(t.tile);
  }
  EXPECT_EQ(region.residentTiles(), tiles);
  EXPECT_EQ(region.map().numCells(), cells);
  region.map().forEachBlock([&](const ndtom::CellIndex& b) { EXPECT_TRUE(kept.count(b)); });
  EXPECT_EQ(region.drops(), region.file().tiles().size() - tiles);

  // The drops' work is the resident blocks once, not once per dropped tile: with four times
  // the tiles (a map twice as wide), four times the blocks examined, not sixteen.
  const std::string wide_path = (dir / "ground-wide.ndtomtiles").string();
  ndtom::saveTiledMap(groundMap(60), wide_path, 1);
  ndtom::localizer::RegionMap wide(wide_path, 10);
  wide.keepEverything();
  const size_t wide_blocks = wide.map().numBlocks();
  wide.keepAround(p);
  EXPECT_GT(wide.drops(), 3 * region.drops());
  EXPECT_LE(region.blocksExamined(), whole.numBlocks());
  EXPECT_LE(wide.blocksExamined(), wide_blocks);
  EXPECT_LE(wide.blocksExamined(), 5 * region.blocksExamined());

  // The same file under a budget that holds a few tiles: refused, naming file and tile,
  // by the region and by the whole-file loader.
  ndtom::localizer::RegionMap small(path, 1000, ndtom::kMinMemoryBudget);
  try {
    small.keepEverything();
    ADD_FAILURE() << "the whole map resident under 1 MB";
  } catch (const ndtom::MemoryBudgetError& e) {
    EXPECT_NE(std::string(e.what()).find(path + " tile ("), std::string::npos) << e.what();
    EXPECT_LE(small.map().memoryBytes(), ndtom::kMinMemoryBudget);
  }
  try {
    (void)region.file().loadAll(ndtom::kMinMemoryBudget);
    ADD_FAILURE() << "loaded under 1 MB";
  } catch (const ndtom::MemoryBudgetError& e) {
    EXPECT_NE(std::string(e.what()).find(path + " tile ("), std::string::npos) << e.what();
  }
}
