// A map moved rigidly: its Gaussians must be those of its points moved (a batch computation
// on the moved points), its occupancy that of the old cell under each new cell's centre
// (brute force over every cell of the moved box), and a whole-cell translation must give the
// map of the translated scans.
#include <gtest/gtest.h>

#include <map>

#include "core/synthetic_room.h"
#include "ndtom/map/rigid_move.h"

using Eigen::Isometry3d;
using Eigen::Vector3d;
using ndtom::CellIndex;
using ndtom::CellStats;
using ndtom::CellView;
using ndtom::MapOptions;
using ndtom::NdtMap;

namespace {

struct Scan {
  Vector3d origin;
  std::vector<Vector3d> points;
};

// The synthetic room seen from a few places near its sensor.
std::vector<Scan> roomScans(int count, unsigned seed) {
  std::vector<Scan> scans;
  for (int i = 0; i < count; ++i)
    scans.push_back({ndtom::testing::kRoomSensor + Vector3d(0.3 * i, -0.2 * i, 0.05 * i),
                     ndtom::testing::sampleRoom(2000, seed + unsigned(i))});
  return scans;
}

NdtMap mapOf(const std::vector<Scan>& scans, const MapOptions& options) {
  NdtMap map(options);
  for (const Scan& s : scans) map.insertScan(s.points, s.origin);
  return map;
}

Isometry3d someMotion() {
  Isometry3d m = Isometry3d::Identity();
  m.linear() = (Eigen::AngleAxisd(0.37, Vector3d::UnitZ()) *
                Eigen::AngleAxisd(0.05, Vector3d(1, 2, 0).normalized()))
                   .toRotationMatrix();
  m.translation() = Vector3d(3.07, -1.31, 0.42);
  return m;
}

// Every cell's statistics, in world coordinates, merged into one: what the map's points are.
CellStats allPoints(const NdtMap& map) {
  CellStats all;
  map.forEachCellOrdered([&](const CellView& c) {
    if (!c.stats) return;
    all.merge(c.stats->shifted(-map.geometry().cellCenter(c.index)));
  });
  return all;
}

}  // namespace

TEST(RigidMove, GaussiansAreTheBatchStatisticsOfTheMovedPoints) {
  MapOptions o;
  o.resolution = 0.25;
  o.occupancy.enabled = false;
  const auto scans = roomScans(5, 21);
  const NdtMap map = mapOf(scans, o);
  const Isometry3d motion = someMotion();
  const NdtMap moved = ndtom::movedMap(map, motion);

  // The oracle: each old cell's points (by batch) go to the cell of their moved mean.
  const ndtom::GridGeometry& grid = map.geometry();
  std::map<CellIndex, std::vector<Vector3d>> old_cells;
  for (const Scan& s : scans)
    for (const Vector3d& p : s.points) old_cells[grid.cellOf(p)].push_back(p);
  std::map<CellIndex, std::vector<Vector3d>> new_cells;
  for (const auto& [index, points] : old_cells) {
    Vector3d mean = Vector3d::Zero();
    for (const Vector3d& p : points) mean += p;
    mean /= double(points.size());
    std::vector<Vector3d>& target = new_cells[grid.cellOf(motion * mean)];
    for (const Vector3d& p : points) target.push_back(motion * p);
  }
  size_t with_stats = 0;
  moved.forEachCell([&](const CellView& c) {
    if (!c.stats) return;
    ++with_stats;
    const auto it = new_cells.find(c.index);
    ASSERT_NE(it, new_cells.end());
    std::vector<Vector3d> relative;
    for (const Vector3d& p : it->second) relative.push_back(p - grid.cellCenter(c.index));
    const CellStats expected = CellStats::fromPoints(relative);
    EXPECT_EQ(c.stats->n, expected.n);
    EXPECT_LT((c.stats->relative_mean - expected.relative_mean).norm(), 1e-9);
    EXPECT_LT((c.stats->scatter - expected.scatter).norm(), 1e-9 * expected.scatter.norm() + 1e-12);
  });
  EXPECT_EQ(with_stats, new_cells.size());
  EXPECT_LT(with_stats, old_cells.size()) << "some cells' points meet in one cell";
}

TEST(RigidMove, KeepsEveryPointAndMovesTheirMeanAndScatter) {
  MapOptions o;
  o.resolution = 0.2;
  const NdtMap map = mapOf(roomScans(4, 8), o);
  const Isometry3d motion = someMotion();
  const NdtMap moved = ndtom::movedMap(map, motion);
  const CellStats before = allPoints(map), after = allPoints(moved);
  EXPECT_EQ(after.n, before.n);
  EXPECT_LT((after.relative_mean - motion * before.relative_mean).norm(), 1e-9);
  const Eigen::Matrix3d rotated = motion.linear() * before.scatter * motion.linear().transpose();
  EXPECT_LT((after.scatter - rotated).norm(), 1e-9 * rotated.norm());
  // And back: the points where they were.
  const CellStats back = allPoints(ndtom::movedMap(moved, motion.inverse()));
  EXPECT_EQ(back.n, before.n);
  EXPECT_LT((back.relative_mean - before.relative_mean).norm(), 1e-9);
  EXPECT_LT((back.scatter - before.scatter).norm(), 1e-9 * before.scatter.norm());
}

TEST(RigidMove, EachCellHasTheOccupancyOfTheOldCellUnderItsCentre) {
  MapOptions o;
  o.resolution = 0.25;
  const NdtMap map = mapOf(roomScans(3, 5), o);
  const Isometry3d motion = someMotion();
  const NdtMap moved = ndtom::movedMap(map, motion);
  const ndtom::GridGeometry& grid = map.geometry();
  // Brute force over the moved box of the old cells.
  CellIndex low{1 << 20, 1 << 20, 1 << 20}, high{-(1 << 20), -(1 << 20), -(1 << 20)};
  map.forEachCell([&](const CellView& c) {
    const CellIndex t = grid.cellOf(motion * grid.cellCenter(c.index));
    low = ndtom::cellwiseMin(low, t);
    high = ndtom::cellwiseMax(high, t);
  });
  size_t resampled = 0, border_stats = 0, occupied = 0;
  for (int x = low.x - 1; x <= high.x + 1; ++x)
    for (int y = low.y - 1; y <= high.y + 1; ++y)
      for (int z = low.z - 1; z <= high.z + 1; ++z) {
        const CellIndex t{x, y, z};
        const auto old_cell = map.cellAt(motion.inverse() * grid.cellCenter(t));
        const auto new_cell = moved.cell(t);
        if (!old_cell) {
          if (new_cell) {
            EXPECT_NE(new_cell->stats, nullptr) << "only points moved past known space";
            ++border_stats;
          }
          continue;
        }
        ++resampled;
        ASSERT_TRUE(new_cell) << "a hole in known space at " << x << " " << y << " " << z;
        if (new_cell->stats) {
          EXPECT_GE(new_cell->logodds, old_cell->logodds);
          EXPECT_GT(new_cell->logodds, 0.f);
        } else {
          EXPECT_EQ(new_cell->logodds, old_cell->logodds);
        }
        occupied += new_cell->logodds > 0;
      }
  EXPECT_EQ(moved.numCells(), resampled + border_stats);
  EXPECT_GT(occupied, 0u);
  // Rotated cells do not map one to one, but the known volume stays about the same.
  EXPECT_NEAR(double(moved.numCells()), double(map.numCells()), 0.05 * map.numCells());
}

TEST(RigidMove, WholeCellTranslationIsTheMapOfTheTranslatedScans) {
  MapOptions o;
  o.resolution = 0.25;
  const auto scans = roomScans(3, 13);
  Isometry3d motion = Isometry3d::Identity();
  motion.translation() = Vector3d(3, -2, 1) * o.resolution;
  auto translated = scans;
  for (Scan& s : translated) {
    s.origin = motion * s.origin;
    for (Vector3d& p : s.points) p = motion * p;
  }
  const NdtMap moved = ndtom::movedMap(mapOf(scans, o), motion);
  const NdtMap expected = mapOf(translated, o);
  EXPECT_EQ(moved.numCells(), expected.numCells());
  expected.forEachCell([&](const CellView& e) {
    const auto c = moved.cell(e.index);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->logodds, e.logodds);
    ASSERT_EQ(c->stats != nullptr, e.stats != nullptr);
    if (!e.stats) return;
    EXPECT_EQ(c->stats->n, e.stats->n);
    EXPECT_LT((c->stats->relative_mean - e.stats->relative_mean).norm(), 1e-12);
    EXPECT_LT((c->stats->scatter - e.stats->scatter).norm(), 1e-12);
  });
}

TEST(RigidMove, IdentityIsACopy) {
  const NdtMap map = mapOf(roomScans(2, 3), MapOptions{});
  const NdtMap same = ndtom::movedMap(map, Isometry3d::Identity());
  EXPECT_EQ(same.numCells(), map.numCells());
  EXPECT_EQ(same.numGaussians(), map.numGaussians());
  map.forEachCell([&](const CellView& c) {
    const auto s = same.cell(c.index);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->logodds, c.logodds);
    ASSERT_EQ(s->stats != nullptr, c.stats != nullptr);
    if (c.stats) {
      EXPECT_LT((s->stats->relative_mean - c.stats->relative_mean).norm(), 1e-12);
    }
  });
}

TEST(RigidMove, BadMotionsThrow) {
  const NdtMap map = mapOf(roomScans(1, 4), MapOptions{});
  Isometry3d nan = Isometry3d::Identity();
  nan.translation().x() = std::nan("");
  EXPECT_THROW((void)ndtom::movedMap(map, nan), std::invalid_argument);
  Isometry3d scaled = Isometry3d::Identity();
  scaled.linear() *= 1.01;
  EXPECT_THROW((void)ndtom::movedMap(map, scaled), std::invalid_argument);
  Isometry3d mirror = Isometry3d::Identity();
  mirror.linear()(2, 2) = -1;
  EXPECT_THROW((void)ndtom::movedMap(map, mirror), std::invalid_argument);
  Isometry3d far = Isometry3d::Identity();
  far.translation().x() = 1e12;
  EXPECT_THROW((void)ndtom::movedMap(map, far), std::invalid_argument);
}
