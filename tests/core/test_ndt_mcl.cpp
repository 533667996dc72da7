// NDT-MCL's likelihood: the scan NDT against batch statistics of its cells (and the kept
// cells against what normal-space sampling must keep), the map table
// against the map's own cell queries, the score against a brute-force sum with full matrix
// inverses, its peak at the true pose, and the edge cases (empty scan, no overlap, a pose
// that is not finite, a floor so small that a product of terms would underflow).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <map>
#include <random>

#include "ndtom/localization/ndt_mcl.h"
#include "ndtom_eval/batch_ndt.h"
#include "synthetic_room.h"

using Eigen::Isometry3d;
using Eigen::Vector3d;
using ndtom::NdtMap;
using ndtom::NdtMclMap;
using ndtom::NdtMclOptions;
using ndtom::ScanNdt;
using ndtom::ScanNdtOptions;

namespace {

Eigen::Matrix3d fullCovariance(const double c[6]) {
  Eigen::Matrix3d m;
  m << c[0], c[1], c[2], c[1], c[3], c[4], c[2], c[4], c[5];
  return m;
}

Isometry3d pose(double x, double y, double z, double yaw, double pitch, double roll) {
  Isometry3d t = Isometry3d::Identity();
  t.linear() =
      (Eigen::AngleAxisd(yaw, Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Vector3d::UnitY()) *
       Eigen::AngleAxisd(roll, Vector3d::UnitX()))
          .toRotationMatrix();
  t.translation() = Vector3d(x, y, z);
  return t;
}

// The room seen from a sensor at `sensor_pose`: world points (seed 2, another sample than
// the map's) in the sensor frame.
std::vector<Vector3d> roomScan(const Isometry3d& sensor_pose, size_t n = 20000) {
  std::vector<Vector3d> points = ndtom::testing::sampleRoom(n, 2);
  for (Vector3d& p : points) p = sensor_pose.inverse() * p;
  return points;
}

// Σ log(c + (1 − c)·exp(−d·l/2)) with the map Gaussian from NdtMap::gaussian() of the
// (occupied) cell holding each moved mean and the summed covariance inverted by Eigen.
double bruteForce(const NdtMap& map, const ScanNdt& scan, const Isometry3d& t, double c, double d) {
  double sum = 0;
  for (const auto& g : scan.gaussians) {
    const Vector3d m = t * g.mean;
    double s = c;
    if (map.geometry().inRange(m)) {
      const auto cell = map.cell(map.geometry().cellOf(m));
      const auto target = map.gaussian(map.geometry().cellOf(m), ndtom::Covariance::Regularized);
      if (target && cell && cell->logodds > 0) {
        const Eigen::Matrix3d summed =
            t.linear() * fullCovariance(g.cov) * t.linear().transpose() + target->covariance;
        const Vector3d e = m - target->mean;
        s += (1 - c) * std::exp(-0.5 * d * e.dot(summed.inverse() * e));
      }
    }
    sum += std::log(s);
  }
  return sum;
}

}  // namespace

TEST(NdtMcl, ScanGaussiansAreTheBatchNdtOfTheirCellsSampledByNormal) {
  const std::vector<Vector3d> points = roomScan(pose(0.3, -0.2, 1.5, 0.3, 0.05, -0.02));
  ScanNdtOptions options;
  options.cell_size = 0.5;
  options.max_gaussians = 40;
  const ScanNdt scan = ndtom::buildScanNdt(points, options);
  EXPECT_EQ(scan.points, points.size());
  EXPECT_EQ(scan.cell_size, 0.5);
  ASSERT_EQ(scan.gaussians.size(), 40u);

  // Oracle: the batch NDT (a hash map of two-pass statistics per cell), each cell's facing
  // axis from its own eigen-decomposition.
  const ndtom::GridGeometry geometry(0.5);
  const ndtom::CellStatsMap batch = ndtom::batchNdt(points, geometry);
  std::map<ndtom::CellIndex, int> axis_of;
  for (const auto& [cell, stats] : batch) {
    if (!stats.hasGaussian()) continue;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(stats.covariance());
    const Vector3d normal = eig.eigenvectors().col(0).cwiseAbs();
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (normal[a] > normal[axis]) axis = a;
    axis_of[cell] = axis;
  }
  EXPECT_EQ(scan.cells_with_gaussian, axis_of.size());

  std::map<ndtom::CellIndex, bool> kept;
  for (const auto& g : scan.gaussians) {
    const ndtom::CellIndex cell = geometry.cellOf(g.mean);
    const auto it = batch.find(cell);
    ASSERT_NE(it, batch.end());
    kept[cell] = true;
    EXPECT_EQ(g.n, it->second.n);
    const Vector3d mean = it->second.relative_mean + geometry.cellCenter(cell);
    EXPECT_LT((g.mean - mean).norm(), 1e-9);
    const Eigen::Matrix3d expected =
        ndtom::regularizedCovariance(it->second.covariance(), ndtom::Regularization{});
    EXPECT_LT((fullCovariance(g.cov) - expected).norm(), 1e-9 * expected.norm());
  }
  for (size_t i = 1; i < scan.gaussians.size(); ++i)
    EXPECT_TRUE(geometry.cellOf(scan.gaussians[i - 1].mean) <
                geometry.cellOf(scan.gaussians[i].mean))
        << "kept ones in cell order";

  // Per facing axis: the kept cells are those with the most points, and the axes share the
  // 40 evenly (within one) unless an axis has fewer cells, which are then all kept.
  size_t taken[3] = {0, 0, 0}, available[3] = {0, 0, 0};
  uint32_t fewest_kept[3] = {UINT32_MAX, UINT32_MAX, UINT32_MAX}, most_left[3] = {0, 0, 0};
  for (const auto& [cell, axis] : axis_of) {
    const uint32_t n = batch.at(cell).n;
    ++available[axis];
    if (kept.count(cell)) {
      ++taken[axis];
      fewest_kept[axis] = std::min(fewest_kept[axis], n);
    } else {
      most_left[axis] = std::max(most_left[axis], n);
    }
  }
  EXPECT_EQ(taken[0] + taken[1] + taken[2], 40u);
  const size_t most_taken = std::max({taken[0], taken[1], taken[2]});
  for (int a = 0; a < 3; ++a) {
    EXPECT_GE(fewest_kept[a], most_left[a]) << "axis " << a;
    EXPECT_TRUE(taken[a] == available[a] || taken[a] + 1 >= most_taken) << "axis " << a;
  }
  EXPECT_GT(std::min({taken[0], taken[1], taken[2]}), 5u) << "the room has all three";
}

TEST(NdtMcl, MapTableFindsWhatTheMapHolds) {
  // Two scans, so that some cells lost their Gaussian to free rays: those must not be found.
  NdtMap map = ndtom::testing::roomMap(0.4, 30000);
  map.insertScan(ndtom::testing::sampleRoom(5000, 7), Vector3d(-1.0, 1.0, 1.2));
  const NdtMclMap table(map);
  size_t expected = 0;
  map.forEachCell([&](const ndtom::CellView& c) {
    expected += c.stats && c.stats->hasGaussian() && c.logodds > 0;
  });
  EXPECT_EQ(table.size(), expected);

  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-5, 5);
  size_t found = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vector3d p(u(rng), u(rng), 0.5 * u(rng) + 1.0);
    const auto g = map.gaussian(map.geometry().cellOf(p), ndtom::Covariance::Regularized);
    const auto cell = map.cellAt(p);
    const ndtom::MclGaussian* hit = table.findAt(p);
    if (!g || !cell || !(cell->logodds > 0)) {
      EXPECT_EQ(hit, nullptr);
      continue;
    }
    ASSERT_NE(hit, nullptr);
    ++found;
    EXPECT_EQ(hit->mean, g->mean);
    // The upper triangle as it is (the regularised matrix is symmetric only to rounding).
    const Eigen::Matrix3d& c = g->covariance;
    const double upper[6] = {c(0, 0), c(0, 1), c(0, 2), c(1, 1), c(1, 2), c(2, 2)};
    for (int k = 0; k < 6; ++k) EXPECT_EQ(hit->cov[k], upper[k]);
  }
  EXPECT_GT(found, 500u);
  EXPECT_EQ(table.findAt(Vector3d(NAN, 0, 0)), nullptr);
  EXPECT_EQ(table.findAt(Vector3d(1e300, 0, 0)), nullptr);
  EXPECT_EQ(NdtMclMap().findAt(Vector3d::Zero()), nullptr);
}

TEST(NdtMcl, ScoreEqualsTheBruteForceSum) {
  const NdtMap map = ndtom::testing::roomMap(0.4, 60000);
  const NdtMclMap table(map);
  const Isometry3d truth = pose(0.3, -0.2, 1.5, 0.3, 0.05, -0.02);
  ScanNdtOptions options;
  options.cell_size = 0.4;
  const ScanNdt scan = ndtom::buildScanNdt(roomScan(truth), options);
  ASSERT_EQ(scan.gaussians.size(), 300u);

  for (const double c : {0.1, 0.01})
    for (const double d : {1.0, 0.05})
      for (const Isometry3d& t :
           {truth, pose(0.5, -0.1, 1.4, 0.25, 0.0, 0.0), pose(2.0, 1.0, 1.0, -1.0, 0.2, 0.1)}) {
        NdtMclOptions o;
        o.outlier_likelihood = c;
        o.exponent_scale = d;
        const auto score = ndtom::ndtMclLikelihood(table, scan, t, o);
        const double expected = bruteForce(map, scan, t, c, d);
        EXPECT_NEAR(score.log_likelihood, expected, 1e-9 * std::abs(expected));
        EXPECT_EQ(score.scored, scan.gaussians.size());
        EXPECT_LE(score.matched, score.scored);
      }
}

TEST(NdtMcl, TruePoseScoresBestAndMatchesMost) {
  const NdtMap map = ndtom::testing::roomMap(0.4, 60000);
  const NdtMclMap table(map);
  const Isometry3d truth = pose(0.3, -0.2, 1.5, 0.3, 0.05, -0.02);
  ScanNdtOptions options;
  options.cell_size = 0.4;
  const ScanNdt scan = ndtom::buildScanNdt(roomScan(truth), options);
  const auto at_truth = ndtom::ndtMclLikelihood(table, scan, truth, NdtMclOptions{});
  EXPECT_GT(at_truth.matched, scan.gaussians.size() * 9 / 10);
  // 0.1 m and 2° along and about each axis, both signs.
  for (int axis = 0; axis < 6; ++axis)
    for (const double sign : {-1.0, 1.0}) {
      double v[6] = {0.3, -0.2, 1.5, 0.3, 0.05, -0.02};
      v[axis] += sign * (axis < 3 ? 0.1 : 2 * M_PI / 180);
      const auto moved = ndtom::ndtMclLikelihood(
          table, scan, pose(v[0], v[1], v[2], v[3], v[4], v[5]), NdtMclOptions{});
      EXPECT_LT(moved.log_likelihood, at_truth.log_likelihood) << "axis " << axis << " " << sign;
    }
}

TEST(NdtMcl, EmptyScanScoresZeroAnywhere) {
  const NdtMclMap table(ndtom::testing::roomMap(0.4, 20000));
  // No points, or too few per cell for a Gaussian, or none finite.
  for (const std::vector<Vector3d>& points :
       {std::vector<Vector3d>{}, std::vector<Vector3d>{{1, 0, 0}, {5, 5, 5}},
        std::vector<Vector3d>(10, Vector3d(NAN, 0, 0))}) {
    const ScanNdt scan = ndtom::buildScanNdt(points, ScanNdtOptions{});
    EXPECT_TRUE(scan.gaussians.empty());
    const auto score =
        ndtom::ndtMclLikelihood(table, scan, Isometry3d::Identity(), NdtMclOptions{});
    EXPECT_EQ(score.log_likelihood, 0.0);
    EXPECT_EQ(score.scored, 0u);
  }
  // An empty map: every Gaussian at the floor.
  const ScanNdt scan = ndtom::buildScanNdt(roomScan(Isometry3d::Identity()), ScanNdtOptions{});
  const auto score =
      ndtom::ndtMclLikelihood(NdtMclMap(NdtMap()), scan, Isometry3d::Identity(), NdtMclOptions{});
  EXPECT_DOUBLE_EQ(score.log_likelihood, double(scan.gaussians.size()) * std::log(0.1));
}

TEST(NdtMcl, NoOverlapScoresTheFloorFiniteAndBelowTheTruth) {
  const NdtMclMap table(ndtom::testing::roomMap(0.4, 60000));
  const Isometry3d truth = pose(0.3, -0.2, 1.5, 0.3, 0.05, -0.02);
  ScanNdtOptions options;
  options.cell_size = 0.4;
  const ScanNdt scan = ndtom::buildScanNdt(roomScan(truth), options);
  const double at_truth =
      ndtom::ndtMclLikelihood(table, scan, truth, NdtMclOptions{}).log_likelihood;
  const double floor = double(scan.gaussians.size()) * std::log(0.1);
  Isometry3d far = truth;
  far.translation() += Vector3d(500, 0, 0);
  Isometry3d nan_pose = truth;
  nan_pose.translation().x() = NAN;
  Isometry3d huge = truth;
  huge.translation().x() = 1e300;
  for (const Isometry3d& t : {far, nan_pose, huge}) {
    const auto score = ndtom::ndtMclLikelihood(table, scan, t, NdtMclOptions{});
    EXPECT_EQ(score.matched, 0u);
    EXPECT_TRUE(std::isfinite(score.log_likelihood));
    EXPECT_NEAR(score.log_likelihood, floor, 1e-9 * std::abs(floor));
    EXPECT_LT(score.log_likelihood, at_truth - 100);
  }
}

TEST(NdtMcl, TinyFloorDoesNotUnderflow) {
  // With c = 1e-200 a product of even two unmatched terms underflows to 0; the runs of terms
  // multiplied before a log must shrink so that the result stays finite and exact.
  const NdtMclMap table(ndtom::testing::roomMap(0.4, 20000));
  const ScanNdt scan = ndtom::buildScanNdt(roomScan(Isometry3d::Identity()), ScanNdtOptions{});
  Isometry3d far = Isometry3d::Identity();
  far.translation().x() = 1000;
  NdtMclOptions o;
  o.outlier_likelihood = 1e-200;
  const double value = ndtom::ndtMclLikelihood(table, scan, far, o).log_likelihood;
  EXPECT_NEAR(value, double(scan.gaussians.size()) * std::log(1e-200), 1e-6);
}

TEST(NdtMcl, BadOptionsAreNamed) {
  const auto message = [](auto options) {
    try {
      ndtom::validate(options);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  ScanNdtOptions s;
  s.cell_size = 0;
  EXPECT_NE(message(s).find("cell_size = 0"), std::string::npos);
  s.cell_size = NAN;
  EXPECT_NE(message(s).find("cell_size"), std::string::npos);
  s = ScanNdtOptions{};
  s.max_gaussians = 0;
  EXPECT_NE(message(s).find("max_gaussians = 0"), std::string::npos);
  EXPECT_THROW(ndtom::buildScanNdt({}, s), std::invalid_argument);
  NdtMclOptions o;
  o.outlier_likelihood = 1;
  EXPECT_NE(message(o).find("outlier_likelihood = 1"), std::string::npos);
  o = NdtMclOptions{};
  o.exponent_scale = -1;
  EXPECT_NE(message(o).find("exponent_scale = -1"), std::string::npos);
  EXPECT_EQ(message(NdtMclOptions{}), "");
  EXPECT_EQ(message(ScanNdtOptions{}), "");
}
