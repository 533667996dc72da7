// NdtMap insertion: Eq. 12 by hand and against a brute-force oracle, RCU against batch,
// bad input, and the all-or-nothing guarantee.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <random>
#include <string>

#include "ndtom/files/map_io.h"
#include "ndtom/map/ndt_map.h"
#include "ndtom_eval/batch_ndt.h"
#include "support/oracle_map.h"

using Eigen::Vector3d;
using ndtom::CellIndex;
using ndtom::MapOptions;
using ndtom::NdtMap;

namespace {

MapOptions unitGrid() {
  MapOptions o;
  o.resolution = 1.0;
  return o;
}

double hitLogOdds() {
  return std::log(0.6 / 0.4);
}
double missLogOdds() {
  return std::log(0.49 / 0.51);
}

float logOddsOf(const NdtMap& map, const CellIndex& c) {
  const auto cell = map.cell(c);
  EXPECT_TRUE(cell.has_value()) << "cell " << c.x << "," << c.y << "," << c.z << " unknown";
  return cell ? cell->logodds : NAN;
}

// A scan of a few surfaces seen from a random origin near the centre of a small world.
std::vector<Vector3d> randomScan(std::mt19937& rng, Vector3d* origin) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  *origin = Vector3d(u(rng), u(rng), 0.3 * u(rng));
  std::vector<Vector3d> pts;
  for (int i = 0; i < 60; ++i) {
    const double a = u(rng), b = u(rng);
    switch (i % 3) {
      case 0:
        pts.emplace_back(3.1 + 0.02 * u(rng), 2.5 * a, 1.5 * b);
        break;  // wall
      case 1:
        pts.emplace_back(2.5 * a, 2.5 * b, -1.2 + 0.02 * u(rng));
        break;  // floor
      default:
        pts.emplace_back(1.0 + 0.3 * a, -1.5 + 0.3 * b, 0.2 * u(rng));
        break;  // box
    }
  }
  return pts;
}

void expectMatchesOracle(const NdtMap& map, const ndtom::testing::OracleMap& oracle) {
  ASSERT_EQ(map.numCells(), oracle.cells().size());
  for (const auto& [index, expected] : oracle.cells()) {
    const auto cell = map.cell(index);
    ASSERT_TRUE(cell.has_value());
    ASSERT_EQ(cell->logodds, expected.logodds)
        << "cell " << index.x << "," << index.y << "," << index.z;
    if (expected.points.empty()) {
      ASSERT_EQ(cell->stats, nullptr);
      continue;
    }
    ASSERT_NE(cell->stats, nullptr);
    ASSERT_EQ(cell->stats->n, expected.points.size());
    const Vector3d centre = map.geometry().cellCenter(index);
    std::vector<Vector3d> relative;
    for (const auto& p : expected.points) relative.push_back(p - centre);
    const ndtom::CellStats batch = ndtom::CellStats::fromPoints(relative);
    ASSERT_LT((cell->stats->relative_mean - batch.relative_mean).norm(), 1e-12);
    ASSERT_LT((cell->stats->scatter - batch.scatter).norm(), 1e-12 * (1 + batch.scatter.norm()));
  }
}

}  // namespace

TEST(NdtMapOccupancy, Eq12ByHand) {
  NdtMap map(unitGrid());
  const Vector3d origin(0.5, 0.5, 0.5);
  // Scan 1: three points in cell (3,0,0); every ray crosses cells 0, 1 and 2.
  auto report = map.insertScan({{3.2, 0.5, 0.5}, {3.5, 0.5, 0.5}, {3.7, 0.6, 0.4}}, origin);
  EXPECT_EQ(report.hits, 3u);
  EXPECT_EQ(report.cells_touched, 4u);
  EXPECT_EQ(report.cells_hit, 1u);
  EXPECT_EQ(report.voxel_visits, 9u);
  EXPECT_NEAR(logOddsOf(map, {3, 0, 0}), 3 * hitLogOdds(), 1e-6);
  for (int x = 0; x < 3; ++x) EXPECT_NEAR(logOddsOf(map, {x, 0, 0}), 3 * missLogOdds(), 1e-6);
  EXPECT_EQ(report.gaussians_gained, 1u);
  EXPECT_TRUE(map.gaussian({3, 0, 0}).has_value());

  // Scan 2: one point in cell 2: a hit there (N_p > 0 wins), misses in cells 0 and 1.
  map.insertScan({{2.5, 0.5, 0.5}}, origin);
  EXPECT_NEAR(logOddsOf(map, {2, 0, 0}), 3 * missLogOdds() + hitLogOdds(), 1e-6);
  EXPECT_NEAR(logOddsOf(map, {1, 0, 0}), 4 * missLogOdds(), 1e-6);
  EXPECT_NEAR(logOddsOf(map, {0, 0, 0}), 4 * missLogOdds(), 1e-6);
  EXPECT_NEAR(logOddsOf(map, {3, 0, 0}), 3 * hitLogOdds(), 1e-6);
  // Cell 2 went from -0.12 to +0.29: occupied, with one point so far and no Gaussian yet.
  ASSERT_TRUE(map.cell({2, 0, 0})->stats);
  EXPECT_EQ(map.cell({2, 0, 0})->stats->n, 1u);
  EXPECT_FALSE(map.gaussian({2, 0, 0}).has_value());
}

TEST(NdtMapOccupancy, ClampingBoundsLogOdds) {
  MapOptions o = unitGrid();
  o.occupancy.logodds_max = 1.0;
  o.occupancy.logodds_min = -0.1;
  NdtMap map(o);
  const Vector3d origin(0.5, 0.5, 0.5);
  for (int i = 0; i < 10; ++i) map.insertScan({{3.5, 0.5, 0.5}, {3.6, 0.5, 0.5}}, origin);
  EXPECT_FLOAT_EQ(logOddsOf(map, {3, 0, 0}), 1.0f);
  EXPECT_FLOAT_EQ(logOddsOf(map, {1, 0, 0}), -0.1f);
  // From the upper clamp, exactly ceil(1.0 / 0.04) free rays empty the cell.
  const int rays_to_empty = int(std::ceil(1.0 / -missLogOdds()));
  for (int i = 0; i < rays_to_empty - 1; ++i) map.insertScan({{6.5, 0.5, 0.5}}, origin);
  EXPECT_GT(logOddsOf(map, {3, 0, 0}), 0.f);
  EXPECT_TRUE(map.cell({3, 0, 0})->stats);
  map.insertScan({{6.5, 0.5, 0.5}}, origin);
  EXPECT_LE(logOddsOf(map, {3, 0, 0}), 0.f);
  EXPECT_FALSE(map.cell({3, 0, 0})->stats);
}

// A box that leaves (later rays pass through it) loses its Gaussians; one that appears gets them.
TEST(NdtMapOccupancy, DynamicObjectsDisappearAndAppear) {
  NdtMap map(unitGrid());
  const Vector3d origin(0.5, 0.5, 0.5);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  auto pointsIn = [&](double x, int n) {
    std::vector<Vector3d> pts;
    for (int i = 0; i < n; ++i) pts.emplace_back(x + u(rng), u(rng), u(rng));
    return pts;
  };
  for (int i = 0; i < 3; ++i) map.insertScan(pointsIn(4, 10), origin);  // object in cell 4
  ASSERT_TRUE(map.gaussian({4, 0, 0}).has_value());
  EXPECT_EQ(map.gaussian({4, 0, 0})->n, 30u);

  // Object gone: the wall behind it at x = 8 is seen through cell 4.
  int scans = 0;
  ndtom::InsertionReport report;
  while (map.gaussian({4, 0, 0}) && scans < 100) {
    report = map.insertScan(pointsIn(8, 10), origin);
    ++scans;
  }
  EXPECT_FALSE(map.gaussian({4, 0, 0}).has_value());
  EXPECT_EQ(report.gaussians_lost, 1u);
  // 3.5 (clamped) minus 10 rays · 0.04 per scan: the ninth scan empties it.
  EXPECT_EQ(scans, int(std::ceil(3.5 / (10 * -missLogOdds()))));

  // Object appears again: hits push the log-odds back above zero and start a fresh Gaussian
  // that holds only the new points.
  int hit_scans = 0;
  while (!map.gaussian({4, 0, 0}) && hit_scans < 100) {
    map.insertScan(pointsIn(4, 5), origin);
    ++hit_scans;
  }
  ASSERT_TRUE(map.gaussian({4, 0, 0}).has_value());
  EXPECT_GT(logOddsOf(map, {4, 0, 0}), 0.f);
  EXPECT_LE(map.gaussian({4, 0, 0})->n, 5u * hit_scans);
}

// In both ray modes: PerHitCell against the oracle's own grouping, one ray per cell of ends
// to their mean (ends beyond max_range in their own groups, free rays only).
TEST(NdtMapOccupancy, MatchesBruteForceOracleOverRandomScans) {
  for (const auto mode : {ndtom::RayMode::PerPoint, ndtom::RayMode::PerHitCell})
    for (const double max_range : {std::numeric_limits<double>::infinity(), 3.0}) {
      SCOPED_TRACE(std::string(ndtom::toString(mode)) + ", max_range " + std::to_string(max_range));
      MapOptions o;
      o.resolution = 0.5;
      o.scan.ray_mode = mode;
      o.scan.max_range = max_range;
      o.scan.min_range = 0.2;
      NdtMap map(o);
      ndtom::testing::OracleMap oracle(o);
      std::mt19937 rng(99);
      for (int scan = 0; scan < 25; ++scan) {
        Vector3d origin;
        const auto pts = randomScan(rng, &origin);
        const auto report = map.insertScan(pts, origin);
        oracle.insert(pts, origin);
        if (std::isfinite(max_range)) {
          EXPECT_GT(report.truncated, 0u);
        }
        expectMatchesOracle(map, oracle);
        if (HasFatalFailure()) return;
      }
    }
}

TEST(NdtMapRecursive, WithoutOccupancyEqualsBatchOfAllPoints) {
  MapOptions o;
  o.resolution = 0.4;
  o.occupancy.enabled = false;
  NdtMap map(o);
  std::mt19937 rng(5);
  std::vector<Vector3d> all;
  for (int scan = 0; scan < 20; ++scan) {
    Vector3d origin;
    const auto pts = randomScan(rng, &origin);
    const auto report = map.insertScan(pts, origin);
    EXPECT_EQ(report.voxel_visits, 0u) << "Recursive NDT casts no rays";
    all.insert(all.end(), pts.begin(), pts.end());
  }
  const auto batch = ndtom::batchNdt(all, map.geometry());
  EXPECT_EQ(map.numCells(), batch.size());
  for (const auto& [index, expected] : batch) {
    const auto cell = map.cell(index);
    ASSERT_TRUE(cell && cell->stats);
    EXPECT_EQ(cell->stats->n, expected.n);
    EXPECT_LT((cell->stats->relative_mean - expected.relative_mean).norm(), 1e-12);
    EXPECT_LT((cell->stats->scatter - expected.scatter).norm(), 1e-12);
  }
}

TEST(NdtMapRecursive, EndsKilometresApartEqualBatchForAnyThreadCount) {
  // Ends 52 km apart on every axis at 1 m: a dense key over their box (49 bits) and the index
  // of one of 70,000 points (17 bits) do not fit one word, so blocks are numbered as met.
  MapOptions o = unitGrid();
  o.occupancy.enabled = false;  // 26 km rays would take long to trace
  o.scan.max_range = std::numeric_limits<double>::infinity();
  std::mt19937 rng(8);
  std::normal_distribution<double> spread(0.0, 0.6);
  std::vector<Vector3d> points;
  const std::vector<Vector3d> centres{{-26000, -26000, -26000},
                                      {26000, 26000, 26000},
                                      {26000, -26000, 5},
                                      {3.5, 2.5, -1.5},
                                      {-12000, 9000, 2}};
  for (int i = 0; i < 70000; ++i)
    points.push_back(centres[size_t(i) % centres.size()] +
                     Vector3d(spread(rng), spread(rng), spread(rng)));
  const auto batch = ndtom::batchNdt(points, ndtom::GridGeometry(o.resolution));
  std::vector<std::vector<uint8_t>> encoded;
  for (const int threads : {1, 2}) {
    o.scan.threads = threads;
    NdtMap map(o);
    const auto report = map.insertScan(points, Vector3d::Zero());
    ASSERT_EQ(report.hits, points.size());
    ASSERT_EQ(map.numCells(), batch.size());
    for (const auto& [index, expected] : batch) {
      const auto cell = map.cell(index);
      ASSERT_TRUE(cell && cell->stats);
      ASSERT_EQ(cell->stats->n, expected.n);
      // km-size coordinates
      ASSERT_LT((cell->stats->relative_mean - expected.relative_mean).norm(), 1e-9);
      ASSERT_LT((cell->stats->scatter - expected.scatter).norm(), 1e-9);
    }
    encoded.push_back(ndtom::encodeMap(map));
  }
  EXPECT_EQ(encoded[0], encoded[1]);
}

TEST(NdtMapInput, BadPointsAreCountedAndChangeNothingElse) {
  MapOptions o;
  o.resolution = 0.5;
  o.scan.min_range = 0.3;
  o.scan.max_range = std::numeric_limits<double>::infinity();  // far points are rejected
  std::mt19937 rng(8);
  Vector3d origin;
  const auto clean = randomScan(rng, &origin);
  std::vector<Vector3d> dirty = clean;
  const double inf = std::numeric_limits<double>::infinity();
  dirty.insert(dirty.begin() + 5, Vector3d(NAN, 0, 0));
  dirty.insert(dirty.begin() + 9, Vector3d(1, inf, 0));
  dirty.push_back(Vector3d(0, 0, -inf));
  dirty.push_back(origin);                        // zero-length ray
  dirty.push_back(origin + Vector3d(0.1, 0, 0));  // closer than min_range
  dirty.push_back(Vector3d(1e12, 0, 0));          // beyond the supported coordinate range
  dirty.push_back(Vector3d(0, -3e8, 0));          // in range, but a ray of 6e8 cells
  dirty.push_back(Vector3d(0, 0, 4e4));

  NdtMap a(o), b(o);
  const auto ra = a.insertScan(clean, origin);
  const auto rb = b.insertScan(dirty, origin);
  EXPECT_EQ(rb.rejected_non_finite, 3u);
  EXPECT_EQ(rb.rejected_too_close, 2u);
  EXPECT_EQ(rb.rejected_out_of_grid, 1u);
  EXPECT_EQ(rb.rejected_too_far, 2u);
  EXPECT_EQ(rb.hits, ra.hits);
  EXPECT_EQ(rb.pointsUsed() + rb.rejected(), dirty.size());
  EXPECT_EQ(ndtom::encodeMap(a), ndtom::encodeMap(b));
}

TEST(NdtMapInput, EmptyScanChangesNothing) {
  NdtMap map;
  std::mt19937 rng(1);
  Vector3d origin;
  map.insertScan(randomScan(rng, &origin), origin);
  const auto before = ndtom::encodeMap(map);
  const auto report = map.insertScan({}, origin);
  EXPECT_EQ(report.cells_touched, 0u);
  EXPECT_EQ(ndtom::encodeMap(map), before);
  map.insertScan({Vector3d(NAN, NAN, NAN)}, origin);
  EXPECT_EQ(ndtom::encodeMap(map), before);
}

TEST(NdtMapInput, BadOriginThrowsAndLeavesTheMap) {
  NdtMap map;
  std::mt19937 rng(2);
  Vector3d origin;
  const auto pts = randomScan(rng, &origin);
  map.insertScan(pts, origin);
  const auto before = ndtom::encodeMap(map);
  EXPECT_THROW(map.insertScan(pts, Vector3d(NAN, 0, 0)), std::invalid_argument);
  EXPECT_THROW(map.insertScan(pts, Vector3d(0, 0, 1e15)), std::invalid_argument);
  ndtom::ScanOptions bad;
  bad.max_range = -1;
  EXPECT_THROW(map.insertScan(pts, origin, bad), std::invalid_argument);
  EXPECT_EQ(ndtom::encodeMap(map), before);
}

TEST(NdtMapInput, MaxRangeTruncatesTheFreeRayAndDropsTheHit) {
  MapOptions o = unitGrid();
  o.scan.max_range = 2.0;
  NdtMap map(o);
  const auto report = map.insertScan({{5.5, 0.5, 0.5}}, {0.5, 0.5, 0.5});
  EXPECT_EQ(report.truncated, 1u);
  EXPECT_EQ(report.hits, 0u);
  // The ray stops at x = 2.5: cells 0 and 1 are free, the cell of the truncated end is not
  // touched, and nothing beyond is.
  EXPECT_TRUE(map.cell({0, 0, 0}));
  EXPECT_TRUE(map.cell({1, 0, 0}));
  EXPECT_FALSE(map.cell({2, 0, 0}));
  EXPECT_FALSE(map.cell({5, 0, 0}));
}

TEST(NdtMapRayModes, PerHitCellCastsOneWeightedRayPerCell) {
  MapOptions o = unitGrid();
  o.scan.ray_mode = ndtom::RayMode::PerHitCell;
  NdtMap map(o);
  const auto report = map.insertScan(
      {{3.2, 0.5, 0.5}, {3.5, 0.5, 0.5}, {3.7, 0.6, 0.4}, {0.5, 3.5, 0.5}}, {0.5, 0.5, 0.5});
  EXPECT_EQ(report.rays_cast, 2u);
  EXPECT_EQ(report.voxel_visits, 3u + 3u);
  EXPECT_NEAR(logOddsOf(map, {1, 0, 0}), 3 * missLogOdds(), 1e-6);  // weight 3
  EXPECT_NEAR(logOddsOf(map, {0, 1, 0}), 1 * missLogOdds(), 1e-6);  // weight 1
  // The origin cell is crossed by both rays.
  EXPECT_NEAR(logOddsOf(map, {0, 0, 0}), 4 * missLogOdds(), 1e-6);
  EXPECT_EQ(map.gaussian({3, 0, 0})->n, 3u);
}

TEST(NdtMapRayModes, HitsAndGaussiansDoNotDependOnTheRayMode) {
  MapOptions per_point;
  per_point.resolution = 0.5;
  per_point.occupancy.logodds_min = -0.5;
  MapOptions per_cell = per_point;
  per_cell.scan.ray_mode = ndtom::RayMode::PerHitCell;
  NdtMap a(per_point), b(per_cell);
  std::mt19937 rng(4);
  for (int i = 0; i < 5; ++i) {
    Vector3d origin;
    const auto pts = randomScan(rng, &origin);
    const auto ra = a.insertScan(pts, origin);
    const auto rb = b.insertScan(pts, origin);
    EXPECT_EQ(ra.hits, rb.hits);
    EXPECT_EQ(ra.cells_hit, rb.cells_hit);
    EXPECT_LT(rb.voxel_visits, ra.voxel_visits);
  }
  // Same points, so the same hits: a cell has bit-identical statistics in both maps unless
  // the free rays of one mode (which cross other cells) emptied it there; an emptied cell is
  // still known, at log-odds <= 0 (cell_rules.h). Every Gaussian is accounted for, both ways.
  const auto compare = [](const NdtMap& x, const NdtMap& y) {
    size_t shared = 0;
    x.forEachCell([&](const ndtom::CellView& c) {
      if (!c.stats || !c.stats->hasGaussian()) return;
      const auto other = y.cell(c.index);
      ASSERT_TRUE(other.has_value()) << "a hit cell unknown in the other mode";
      if (!other->stats || other->stats->n == 0) {
        EXPECT_LE(other->logodds, 0.f) << "statistics lost without the cell being emptied";
        return;
      }
      EXPECT_EQ(other->stats->n, c.stats->n);
      EXPECT_EQ(other->stats->relative_mean, c.stats->relative_mean);
      EXPECT_EQ(other->stats->scatter, c.stats->scatter);
      ++shared;
    });
    return shared;
  };
  const size_t shared = compare(a, b);
  EXPECT_EQ(compare(b, a), shared);
  EXPECT_GT(shared, 0u);
}

TEST(NdtMapQueries, CoordinatesUseFloorIncludingNegatives) {
  NdtMap map(unitGrid());
  map.insertScan({{-2.5, -0.5, 0.5}, {-2.6, -0.4, 0.5}, {-2.4, -0.6, 0.5}}, {0.5, 0.5, 0.5});
  const auto c = map.cellAt({-2.01, -0.99, 0.0});
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->index, (CellIndex{-3, -1, 0}));
  ASSERT_TRUE(map.gaussian({-3, -1, 0}));
  EXPECT_TRUE(map.gaussian({-3, -1, 0})->mean.isApprox(Vector3d(-2.5, -0.5, 0.5)));
  EXPECT_FALSE(map.cellAt({NAN, 0, 0}).has_value());
  EXPECT_FALSE(map.occupancyProbability({100, 100, 100}).has_value());
  EXPECT_GT(*map.occupancyProbability({-2.5, -0.5, 0.5}), 0.5);
}

TEST(NdtMapQueries, RegularisedCovarianceIsFlooredButStatisticsStayExact) {
  NdtMap map(unitGrid());
  // A perfectly planar patch: singular covariance.
  std::vector<Vector3d> pts;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) pts.emplace_back(3.1 + 0.2 * i, 0.1 + 0.2 * j, 0.5);
  map.insertScan(pts, {0.5, 0.5, 0.5});
  const auto exact = map.gaussian({3, 0, 0}, ndtom::Covariance::Exact);
  const auto reg = map.gaussian({3, 0, 0}, ndtom::Covariance::Regularized);
  ASSERT_TRUE(exact && reg);
  EXPECT_NEAR(exact->covariance.determinant(), 0.0, 1e-15);
  EXPECT_GT(reg->covariance.determinant(), 0.0);
  const double lambda_max = exact->covariance.diagonal().maxCoeff();
  EXPECT_NEAR(reg->covariance(2, 2), 0.01 * lambda_max, 1e-12);
  EXPECT_EQ(map.cell({3, 0, 0})->stats->scatter(2, 2), 0.0) << "regularisation written back";
}

TEST(NdtMapThreads, AnyThreadCountGivesTheSameMap) {
  for (const auto mode : {ndtom::RayMode::PerPoint, ndtom::RayMode::PerHitCell}) {
    MapOptions o;
    o.resolution = 0.3;
    o.scan.ray_mode = mode;
    std::vector<NdtMap> maps;
    for (const int threads : {1, 2, 3}) {
      o.scan.threads = threads;
      NdtMap map(o);
      std::mt19937 rng(21);
      for (int scan = 0; scan < 6; ++scan) {
        Vector3d origin;
        auto pts = randomScan(rng, &origin);
        for (int copy = 0; copy < 20; ++copy)  // enough rays to be split over threads
          for (size_t i = 0; i < 60; ++i) pts.push_back(pts[i] + Vector3d(0.01 * copy, 0, 0));
        map.insertScan(pts, origin);
      }
      maps.push_back(std::move(map));
    }
    EXPECT_EQ(ndtom::encodeMap(maps[0]), ndtom::encodeMap(maps[1]));
    EXPECT_EQ(ndtom::encodeMap(maps[0]), ndtom::encodeMap(maps[2]));
  }
}

TEST(NdtMapThreads, BadThreadCountIsRejected) {
  ndtom::ScanOptions o;
  o.threads = 0;
  EXPECT_THROW(ndtom::validate(o), std::invalid_argument);
  o.threads = 100000;
  EXPECT_THROW(ndtom::validate(o), std::invalid_argument);
}
