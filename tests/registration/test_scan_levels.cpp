// The scan's levels (grouping by cell, regrouping, the usable points) against a brute-force
// grouping, and the same bits for any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>

#include "ndtom_io/pcd_reader.h"
#include "registration/scan_levels.h"
#include "registration/usable_points.h"

using namespace ndtom;
using namespace ndtom::registration;
using Eigen::Vector3d;

namespace {

const std::string kBalm = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld";

// A shipped lidar scan (sensor frame), with a few NaN, inf and far points mixed in.
std::vector<Vector3d> realScan() {
  std::vector<Vector3d> points = io::readPcd(kBalm + "/full3.pcd").points;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < points.size(); i += 997) points[i] = Vector3d(nan, 0, 1);
  for (size_t i = 500; i < points.size(); i += 1009) points[i] = Vector3d(1, -inf, 0);
  for (size_t i = 700; i < points.size(); i += 1013) points[i] *= 1e4;
  return points;
}

// Brute force: a std::map from cell to its points in scan order.
std::vector<ScanCell> groupByMap(const std::vector<Vector3d>& points, double cell_size) {
  std::map<CellIndex, std::vector<Vector3d>> members;
  for (const Vector3d& p : points)
    members[GridGeometry::floorCell(p / cell_size)].push_back(p);
  std::vector<ScanCell> out;
  for (const auto& [cell, ps] : members) out.push_back({cell, CellStats::fromPoints(ps)});
  return out;
}

void expectSameCells(const std::vector<ScanCell>& a, const std::vector<ScanCell>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].cell, b[i].cell) << i;
    ASSERT_EQ(a[i].stats.n, b[i].stats.n) << i;
    ASSERT_EQ(a[i].stats.relative_mean, b[i].stats.relative_mean) << i;
    ASSERT_EQ(a[i].stats.scatter, b[i].stats.scatter) << i;
  }
}

void expectSameLevels(const std::vector<ScanLevel>& a, const std::vector<ScanLevel>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t l = 0; l < a.size(); ++l) {
    ASSERT_EQ(a[l].points, b[l].points) << "level " << l;
    ASSERT_EQ(a[l].gaussians.size(), b[l].gaussians.size()) << "level " << l;
    for (size_t i = 0; i < a[l].gaussians.size(); ++i) {
      ASSERT_EQ(a[l].gaussians[i].mean, b[l].gaussians[i].mean);
      ASSERT_EQ(a[l].gaussians[i].covariance, b[l].gaussians[i].covariance);
      ASSERT_EQ(a[l].gaussians[i].max_variance, b[l].gaussians[i].max_variance);
    }
  }
}

}  // namespace

TEST(ScanLevels, UsablePointsAreTheSameForAnyThreadCount) {
  const std::vector<Vector3d> scan = realScan();
  const std::vector<Vector3d> serial = usablePoints(scan, 0.5, 60, 0.05);
  size_t expected = 0;
  for (const Vector3d& p : scan)
    expected += p.allFinite() && p.norm() >= 0.5 && p.norm() <= 60;
  EXPECT_EQ(serial.size(), expected);
  WorkerPool pool;
  for (const size_t threads : {2, 3, 7})
    EXPECT_EQ(usablePoints(scan, 0.5, 60, 0.05, {pool, threads}), serial);
}

TEST(ScanLevels, GroupingMatchesABruteForceGroupingOnAnyThreadCount) {
  const std::vector<Vector3d> points = usablePoints(realScan(), 0.5, 60, 0.05);
  ASSERT_GT(points.size(), 20000u);  // several parts of 2048 items for every thread count
  for (const double cell : {0.1, 0.8}) {
    const std::vector<ScanCell> expected = groupByMap(points, cell);
    WorkerPool pool;
    for (const size_t threads : {1, 2, 3, 7}) {
      SCOPED_TRACE(::testing::Message() << cell << " m, " << threads << " threads");
      expectSameCells(groupPoints(points, cell, {pool, threads}), expected);
    }
  }
}

TEST(ScanLevels, RegroupingMergesTheCellsWhoseMeanFallsInEachCoarseCell) {
  const std::vector<Vector3d> points = usablePoints(realScan(), 0.5, 60, 0.05);
  WorkerPool pool;
  const std::vector<ScanCell> fine = groupPoints(points, 0.1, {pool, 1});
  // Brute force: merge in the fine cells' order, keyed by the coarse cell of each mean.
  std::map<CellIndex, CellStats> merged;
  for (const ScanCell& c : fine)
    merged[GridGeometry::floorCell(c.stats.relative_mean / 0.4)].merge(c.stats);
  std::vector<ScanCell> expected;
  for (const auto& [cell, stats] : merged) expected.push_back({cell, stats});
  uint64_t total = 0;
  for (const ScanCell& c : expected) total += c.stats.n;
  EXPECT_EQ(total, points.size());
  for (const size_t threads : {1, 2, 5}) expectSameCells(regroup(fine, 0.4, {pool, threads}), expected);
}

TEST(ScanLevels, LevelsAreTheSameBitsForAnyThreadCount) {
  const std::vector<Vector3d> points = usablePoints(realScan(), 0.5, 60, 0.05);
  const Regularization regularization;
  for (const auto method : {RegistrationMethod::P2D, RegistrationMethod::D2D}) {
    RegistrationOptions o;
    o.method = method;
    o.voxel_ratio = 0.25;
    const std::vector<double> resolutions{1.6, 0.8, 0.4, 0.2};
    const std::vector<ScanLevel> serial = buildScanLevels(points, resolutions, o, regularization);
    ASSERT_EQ(serial.size(), resolutions.size());
    EXPECT_GT(serial.back().size(), serial.front().size());  // finer levels hold more
    WorkerPool pool;
    for (const size_t threads : {2, 4}) {
      SCOPED_TRACE(::testing::Message() << toString(method) << ", " << threads << " threads");
      expectSameLevels(buildScanLevels(points, resolutions, o, regularization, {pool, threads}),
                       serial);
    }
  }
}

TEST(ScanLevels, FewPointsAndNoPointsGiveTheSerialResult) {
  WorkerPool pool;
  const std::vector<Vector3d> none;
  EXPECT_TRUE(groupPoints(none, 0.2, {pool, 4}).empty());
  EXPECT_TRUE(usablePoints(none, 0, 10, 0.2, {pool, 4}).empty());
  std::mt19937 rng(5);
  std::normal_distribution<double> d(0, 3);
  std::vector<Vector3d> few;
  for (int i = 0; i < 50; ++i) few.emplace_back(d(rng), d(rng), d(rng));
  expectSameCells(groupPoints(few, 0.5, {pool, 4}), groupByMap(few, 0.5));
}
