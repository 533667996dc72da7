// RCU (Eq. 2, 3, 11) against the batch estimate (Eq. 1) computed in long double.
#include <gtest/gtest.h>

#include <random>

#include "ndtom/map/cell_stats.h"

using Eigen::Matrix3d;
using Eigen::Vector3d;
using ndtom::CellStats;

namespace {

struct BatchOracle {
  Vector3d mean;
  Matrix3d covariance;
};

// Two-pass estimate in extended precision: the independent reference.
BatchOracle batchEstimate(const std::vector<Vector3d>& points) {
  long double sum[3] = {0, 0, 0};
  for (const auto& p : points)
    for (int a = 0; a < 3; ++a) sum[a] += p[a];
  long double mean[3];
  for (int a = 0; a < 3; ++a) mean[a] = sum[a] / points.size();
  long double s[3][3] = {};
  for (const auto& p : points)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) s[a][b] += (p[a] - mean[a]) * (p[b] - mean[b]);
  BatchOracle out;
  for (int a = 0; a < 3; ++a) {
    out.mean[a] = double(mean[a]);
    for (int b = 0; b < 3; ++b) out.covariance(a, b) = double(s[a][b] / (points.size() - 1));
  }
  return out;
}

// Points of a flattened blob (like a surface patch in a cell) around `centre`.
std::vector<Vector3d> randomPoints(size_t n, const Vector3d& centre, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Vector3d> pts(n);
  for (auto& p : pts) p = centre + Vector3d(0.05 * g(rng), 0.03 * g(rng), 0.004 * g(rng));
  return pts;
}

// RCU over random batches, with the mean kept relative to `reference` as the map does.
CellStats recursiveEstimate(const std::vector<Vector3d>& points, const Vector3d& reference,
                            std::mt19937& rng) {
  CellStats stats;
  std::uniform_int_distribution<size_t> batch_size(1, 40);
  for (size_t begin = 0; begin < points.size();) {
    const size_t end = std::min(points.size(), begin + batch_size(rng));
    std::vector<Vector3d> batch;
    for (size_t i = begin; i < end; ++i) batch.push_back(points[i] - reference);
    stats.merge(CellStats::fromPoints(batch));
    begin = end;
  }
  return stats;
}

double relativeError(const Matrix3d& a, const Matrix3d& b) {
  return (a - b).norm() / b.norm();
}

}  // namespace

TEST(CellStats, RecursiveUpdateEqualsBatchOnRandomBatches) {
  std::mt19937 rng(42);
  for (int trial = 0; trial < 50; ++trial) {
    const Vector3d centre(0.1 * trial, -0.2, 1.5);
    const auto points = randomPoints(500 + 37 * trial, centre, rng);
    const CellStats rcu = recursiveEstimate(points, centre, rng);
    const BatchOracle batch = batchEstimate(points);
    ASSERT_EQ(rcu.n, points.size());
    EXPECT_LT((centre + rcu.relative_mean - batch.mean).norm() / batch.mean.norm(), 1e-12);
    EXPECT_LT(relativeError(rcu.covariance(), batch.covariance), 1e-9);
  }
}

// UTM-like coordinates: all points offset by 1e6 m. The map keeps means relative to the cell
// centre, so RCU stays exact. The sum-of-squares form (Σx, Σxxᵀ), which the paper rejects
// after Chan et al., loses every digit here: xxᵀ ≈ 1e12 m² has an ulp of ~1e-4 m², larger
// than the covariance (~1e-3 m²) it is meant to resolve.
TEST(CellStats, RecursiveUpdateStaysExactFarFromOrigin) {
  std::mt19937 rng(7);
  const Vector3d centre(1e6 + 0.35, 1e6 - 0.15, 1e6 + 0.05);
  const auto points = randomPoints(2000, centre, rng);
  const BatchOracle batch = batchEstimate(points);

  const CellStats rcu = recursiveEstimate(points, centre, rng);
  EXPECT_LT((centre + rcu.relative_mean - batch.mean).norm() / batch.mean.norm(), 1e-15);
  EXPECT_LT(relativeError(rcu.covariance(), batch.covariance), 1e-9);

  Vector3d sum = Vector3d::Zero();
  Matrix3d sum_sq = Matrix3d::Zero();
  for (const auto& p : points) {
    sum += p;
    sum_sq += p * p.transpose();
  }
  const double n = double(points.size());
  const Matrix3d naive = (sum_sq - sum * sum.transpose() / n) / (n - 1);
  EXPECT_GT(relativeError(naive, batch.covariance), 1e-2) << "the sum-of-squares form should fail";
}

TEST(CellStats, GaussianNeedsThreePoints) {
  CellStats s = CellStats::fromPoints({Vector3d(0, 0, 0), Vector3d(0.1, 0, 0)});
  EXPECT_FALSE(s.hasGaussian());
  s.merge(CellStats::fromPoints({Vector3d(0, 0.1, 0)}));
  EXPECT_TRUE(s.hasGaussian());
  EXPECT_EQ(s.n, 3u);
}

TEST(CellStats, MergingEmptyIsIdentity) {
  std::mt19937 rng(1);
  const CellStats a = CellStats::fromPoints(randomPoints(10, Vector3d::Zero(), rng));
  CellStats b = a;
  b.merge(CellStats{});
  EXPECT_EQ(b.n, a.n);
  EXPECT_EQ(b.relative_mean, a.relative_mean);
  EXPECT_EQ(b.scatter, a.scatter);
  CellStats c;
  c.merge(a);
  EXPECT_EQ(c.relative_mean, a.relative_mean);
  EXPECT_EQ(c.scatter, a.scatter);
}

TEST(CellStats, ShiftedMovesOnlyTheMean) {
  std::mt19937 rng(3);
  const auto pts = randomPoints(20, Vector3d(1, 2, 3), rng);
  const CellStats a = CellStats::fromPoints(pts);
  const CellStats b = a.shifted(Vector3d(1, 2, 3));
  EXPECT_TRUE(b.relative_mean.isApprox(a.relative_mean - Vector3d(1, 2, 3)));
  EXPECT_EQ(b.scatter, a.scatter);
}
