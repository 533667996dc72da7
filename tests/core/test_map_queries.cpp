// Point occupancy and ray casting against independent computations: the log-odds read cell by
// cell, and a brute-force ray-box intersection with every occupied cell.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/synthetic_room.h"
#include "ndtom/map/map_queries.h"

namespace {

using ndtom::CellState;

TEST(MapQueries, StateAtEveryKnownCellFollowsItsLogOdds) {
  const ndtom::NdtMap map = ndtom::testing::roomMap(0.2, 20000);
  size_t occupied = 0, free = 0;
  map.forEachCell([&](const ndtom::CellView& c) {
    const Eigen::Vector3d centre = map.geometry().cellCenter(c.index);
    const CellState expected = c.logodds > 0.f   ? CellState::Occupied
                               : c.logodds < 0.f ? CellState::Free
                                                 : CellState::Unknown;
    ASSERT_EQ(ndtom::stateAt(map, centre), expected);
    occupied += expected == CellState::Occupied;
    free += expected == CellState::Free;
  });
  EXPECT_EQ(occupied, map.numOccupied());
  EXPECT_GT(free, occupied);  // a scan sees more free space than surface
  EXPECT_TRUE(ndtom::isUnknown(map, Eigen::Vector3d(50, 50, 50)));
  EXPECT_TRUE(ndtom::isUnknown(map, Eigen::Vector3d(std::nan(""), 0, 0)));
  EXPECT_TRUE(ndtom::isUnknown(map, Eigen::Vector3d(1e300, 0, 0)));
  EXPECT_TRUE(ndtom::isFree(map, ndtom::testing::kRoomSensor + Eigen::Vector3d(0, 0, -0.5)));
}

TEST(MapQueries, WithoutOccupancyCellsWithPointsAreOccupiedAndNothingIsFree) {
  ndtom::MapOptions options;
  options.occupancy.enabled = false;
  ndtom::NdtMap map(options);
  map.insertScan(ndtom::testing::sampleRoom(5000, 2), ndtom::testing::kRoomSensor);
  size_t cells = 0;
  map.forEachCell([&](const ndtom::CellView& c) {
    const bool has_points = c.stats && c.stats->n > 0;
    ASSERT_EQ(ndtom::stateAt(map, map.geometry().cellCenter(c.index)),
              has_points ? CellState::Occupied : CellState::Unknown);
    cells += has_points;
  });
  EXPECT_GT(cells, 100u);
  EXPECT_EQ(map.numOccupied(), cells) << "numOccupied and cellState disagree";
}

// numOccupied() counts by cellState()'s rule: a known cell at log-odds 0 is unknown, not
// occupied (nor free).
TEST(MapQueries, NumOccupiedFollowsCellState) {
  ndtom::NdtMap map{ndtom::MapOptions{}};
  ASSERT_TRUE(map.setCell({0, 0, 0}, 0.f, {}));
  ASSERT_TRUE(map.setCell({1, 0, 0}, -1.f, {}));
  ASSERT_TRUE(map.setCell({2, 0, 0}, 1.f, {}));
  ASSERT_TRUE(map.setCell({3, 0, 0}, 2.f, {}));
  size_t occupied = 0;
  map.forEachCell([&](const ndtom::CellView& c) {
    occupied += ndtom::cellState(map, c) == CellState::Occupied;
  });
  EXPECT_EQ(occupied, 2u);
  EXPECT_EQ(map.numOccupied(), 2u);
  EXPECT_EQ(ndtom::cellState(map, *map.cell({0, 0, 0})), CellState::Unknown)
      << "log-odds 0 is neither free nor occupied";
  EXPECT_EQ(ndtom::cellState(map, *map.cell({1, 0, 0})), CellState::Free);

  // Occupancy off (Recursive NDT): a cell with points is occupied whatever its log-odds (one
  // at 0, as a file or setCell may hold it, was not counted by "log-odds > 0").
  ndtom::MapOptions recursive_options;
  recursive_options.occupancy.enabled = false;
  ndtom::NdtMap recursive(recursive_options);
  const ndtom::CellStats points =
      ndtom::CellStats::fromPoints({{0.01, 0.02, 0}, {-0.03, 0.01, 0.02}, {0.02, -0.01, -0.01}});
  ASSERT_TRUE(recursive.setCell({0, 0, 0}, 0.f, points));
  ASSERT_EQ(ndtom::cellState(recursive, *recursive.cell({0, 0, 0})), CellState::Occupied);
  EXPECT_EQ(recursive.numOccupied(), 1u);
}

// Entry distance of the ray into the closed box of `cell`, if it meets it within [0, range].
std::optional<double> slabEntry(const ndtom::NdtMap& map, const ndtom::CellIndex& cell,
                                const Eigen::Vector3d& o, const Eigen::Vector3d& u, double range) {
  double enter = 0, leave = range;
  for (int a = 0; a < 3; ++a) {
    const double lo = map.geometry().cellMin(cell[a]), hi = map.geometry().cellMin(cell[a] + 1);
    if (u[a] == 0) {
      if (o[a] < lo || o[a] >= hi) return std::nullopt;
      continue;
    }
    const double t0 = (lo - o[a]) / u[a], t1 = (hi - o[a]) / u[a];
    enter = std::max(enter, std::min(t0, t1));
    leave = std::min(leave, std::max(t0, t1));
  }
  if (enter > leave) return std::nullopt;
  return enter;
}

TEST(MapQueries, CastRayFindsTheNearestOccupiedCellThatBruteForceFinds) {
  const ndtom::NdtMap map = ndtom::testing::roomMap(0.2, 20000);
  std::vector<ndtom::CellIndex> occupied;
  map.forEachCell([&](const ndtom::CellView& c) {
    if (c.logodds > 0.f) occupied.push_back(c.index);
  });
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  int hits = 0, misses = 0;
  for (int k = 0; k < 400; ++k) {
    const Eigen::Vector3d origin =
        ndtom::testing::kRoomSensor + Eigen::Vector3d(u(rng), u(rng), 0.5 * u(rng));
    const Eigen::Vector3d direction(u(rng), u(rng), u(rng));
    const double range = k % 4 == 0 ? 1.5 : 12.0;  // some end before any surface
    const Eigen::Vector3d unit = direction.normalized();
    std::optional<double> best;
    for (const auto& cell : occupied) {
      const auto t = slabEntry(map, cell, origin, unit, range);
      if (t && (!best || *t < *best)) best = t;
    }
    const auto hit = ndtom::castRay(map, origin, direction, range);
    ASSERT_EQ(hit.has_value(), best.has_value()) << "ray " << k;
    if (!hit) {
      ++misses;
      continue;
    }
    ++hits;
    EXPECT_NEAR(hit->distance, *best, 1e-9) << "ray " << k;
    EXPECT_TRUE(ndtom::isOccupied(map, map.geometry().cellCenter(hit->cell)));
    EXPECT_NEAR((hit->point - origin).norm(), hit->distance, 1e-9);
  }
  EXPECT_GT(hits, 150);
  EXPECT_GT(misses, 20);
}

TEST(MapQueries, CastRayStoppingAtUnknownNeverLooksThroughUnexploredCells) {
  const ndtom::NdtMap map = ndtom::testing::roomMap(0.2, 20000);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  int stopped = 0, hit_through_known = 0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d origin = ndtom::testing::kRoomSensor;
    const Eigen::Vector3d unit = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const auto through = ndtom::castRay(map, origin, unit, 12.0);
    const auto careful = ndtom::castRay(map, origin, unit, 12.0, true);
    const double until = careful ? careful->distance : (through ? through->distance : 12.0);
    // Sampled densely, the ray before the reported hit crosses no unknown cell.
    bool unknown_before = false;
    for (double t = 0; t < until - 1e-6; t += 0.002)
      unknown_before |= ndtom::isUnknown(map, origin + t * unit);
    if (careful) {
      ASSERT_TRUE(through) << "ray " << k;
      EXPECT_EQ(careful->cell, through->cell) << "ray " << k;
      EXPECT_FALSE(unknown_before) << "ray " << k;
      ++hit_through_known;
    } else if (through) {
      EXPECT_TRUE(unknown_before) << "ray " << k;  // stopped by an unknown cell on the way
      ++stopped;
    }
  }
  EXPECT_GT(hit_through_known, 100);
  EXPECT_GT(stopped, 0);
}

TEST(MapQueries, CastRayRefusesBadRays) {
  const ndtom::NdtMap map = ndtom::testing::roomMap(0.2, 2000);
  const Eigen::Vector3d o = ndtom::testing::kRoomSensor;
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(ndtom::castRay(map, o, Eigen::Vector3d::Zero(), 5), std::invalid_argument);
  EXPECT_THROW(ndtom::castRay(map, o, Eigen::Vector3d(1, 0, 0), inf), std::invalid_argument);
  EXPECT_THROW(ndtom::castRay(map, o, Eigen::Vector3d(1, 0, 0), -1), std::invalid_argument);
  EXPECT_THROW(ndtom::castRay(map, Eigen::Vector3d(std::nan(""), 0, 0), Eigen::Vector3d(1, 0, 0), 5),
               std::invalid_argument);
  EXPECT_THROW(ndtom::castRay(map, o, Eigen::Vector3d(1, 0, 0), 1e12), std::invalid_argument);
  // A zero range looks at the origin's own cell only.
  EXPECT_FALSE(ndtom::castRay(map, o, Eigen::Vector3d(1, 0, 0), 0));
}

}  // namespace
