// The paper's map similarity ("mean L2", Sec. IV-A): exact identities, monotonicity, per-cell
// symmetry, and agreement with closed forms and with a direct evaluation of the densities.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "ndtom/map/ndt_map.h"
#include "ndtom_eval/batch_ndt.h"
#include "ndtom_eval/map_similarity.h"

using Eigen::Matrix3d;
using Eigen::Vector3d;
using ndtom::CellIndex;
using ndtom::Gaussian;
using ndtom::GaussianSet;

namespace {

Matrix3d randomCovariance(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Matrix3d a;
  for (int i = 0; i < 9; ++i) a(i) = 0.1 * u(rng);
  return a * a.transpose() + 1e-4 * Matrix3d::Identity();
}

GaussianSet randomSet(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  GaussianSet set;
  for (int i = 0; i < count; ++i) {
    Gaussian g;
    g.cell = CellIndex{i, -i, 2 * i};
    g.n = 10;
    g.mean = Vector3d(u(rng), u(rng), u(rng)) * 5.0;
    g.covariance = randomCovariance(rng);
    set.emplace(g.cell, g);
  }
  return set;
}

// Densities written out directly: N(μ_f; μ_g, P_f + P_g) / sqrt(N(0; 0, 2P_f) N(0; 0, 2P_g)).
double directSimilarity(const Gaussian& f, const Gaussian& g) {
  auto density = [](const Vector3d& d, const Matrix3d& cov) {
    return std::exp(-0.5 * d.dot(cov.inverse() * d)) /
           std::sqrt(std::pow(2 * M_PI, 3) * cov.determinant());
  };
  const double fg = density(f.mean - g.mean, f.covariance + g.covariance);
  const double ff = density(Vector3d::Zero(), 2 * f.covariance);
  const double gg = density(Vector3d::Zero(), 2 * g.covariance);
  return fg / std::sqrt(ff * gg);
}

TEST(MapSimilarity, IdenticalMapsGiveExactlyOne) {
  const GaussianSet set = randomSet(500, 1);
  const GaussianSet copy = set;
  EXPECT_EQ(ndtom::mapSimilarity(set, set), 1.0);
  EXPECT_EQ(ndtom::mapSimilarity(copy, set), 1.0);
  for (const auto& [cell, g] : set) EXPECT_EQ(ndtom::gaussianSimilarity(g, g), 1.0);
}

TEST(MapSimilarity, IdenticalRealMapsGiveExactlyOne) {
  // A map built twice from the same real-looking surface data.
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<Vector3d> points;
  for (int i = 0; i < 20000; ++i)
    points.emplace_back(0.001 * i - 7.3, 0.5 * std::sin(0.01 * i), -1.2 + noise(rng));
  ndtom::MapOptions options;
  options.occupancy.enabled = false;
  ndtom::NdtMap a(options), b(options);
  a.insertScan(points, Vector3d(0, 0, 1));
  b.insertScan(points, Vector3d(0, 0, 1));
  ASSERT_GT(a.numGaussians(), 50u);
  EXPECT_EQ(ndtom::mapSimilarity(ndtom::gaussianSetOf(a), ndtom::gaussianSetOf(b)), 1.0);
}

TEST(MapSimilarity, DecreasesMonotonicallyWithMeanShift) {
  const GaussianSet reference = randomSet(200, 2);
  const Vector3d direction = Vector3d(1, -2, 0.5).normalized();
  double previous = 1.0;
  for (int step = 1; step <= 40; ++step) {
    GaussianSet shifted = reference;
    for (auto& [cell, g] : shifted) g.mean += 0.01 * step * direction;
    const double s = ndtom::mapSimilarity(shifted, reference);
    EXPECT_LT(s, previous) << "shift " << 0.01 * step << " m";
    EXPECT_GT(s, 0.0);
    previous = s;
  }
  EXPECT_LT(previous, 0.5);  // 0.4 m is well beyond these Gaussians' spread
}

TEST(MapSimilarity, SymmetricPerCell) {
  const GaussianSet a = randomSet(300, 4), b = randomSet(300, 5);
  for (const auto& [cell, f] : a) {
    const Gaussian& g = b.at(cell);
    EXPECT_EQ(ndtom::gaussianSimilarity(f, g), ndtom::gaussianSimilarity(g, f));
  }
}

TEST(MapSimilarity, MatchesDirectDensityEvaluation) {
  const GaussianSet a = randomSet(300, 6), b = randomSet(300, 7);
  for (const auto& [cell, f] : a) {
    Gaussian g = b.at(cell);
    g.mean = f.mean + 0.05 * (g.mean - f.mean);  // near enough for non-negligible values
    const double expected = directSimilarity(f, g);
    EXPECT_NEAR(ndtom::gaussianSimilarity(f, g), expected, 1e-10 + 1e-9 * expected);
  }
}

TEST(MapSimilarity, IsotropicClosedForm) {
  // Equal isotropic covariances σ²I at distance d: s = exp(−d² / (4σ²)).
  Gaussian f, g;
  f.covariance = g.covariance = 0.04 * Matrix3d::Identity();
  for (double d : {0.0, 0.1, 0.3, 0.7}) {
    g.mean = Vector3d(0, d, 0);
    EXPECT_NEAR(ndtom::gaussianSimilarity(f, g), std::exp(-d * d / (4 * 0.04)), 1e-14);
  }
  // Concentric, σ_f = 1, σ_g = 2 per axis: s = (2·1·2 / (1 + 4))^(3/2).
  f.covariance = Matrix3d::Identity();
  g.covariance = 4 * Matrix3d::Identity();
  g.mean = f.mean;
  EXPECT_NEAR(ndtom::gaussianSimilarity(f, g), std::pow(0.8, 1.5), 1e-14);
}

TEST(MapSimilarity, NormalisedByTheReferenceCount) {
  const GaussianSet reference = randomSet(4, 8);
  GaussianSet test;
  int kept = 0;
  for (const auto& [cell, g] : reference)
    if (kept++ < 2) test.emplace(cell, g);
  Gaussian stray = reference.begin()->second;
  stray.cell = CellIndex{1000, 1000, 1000};  // no counterpart: contributes 0
  test.emplace(stray.cell, stray);
  EXPECT_EQ(ndtom::mapSimilarity(test, reference), 0.5);
  EXPECT_EQ(ndtom::mapSimilarity(reference, test), 2.0 / 3.0);
  EXPECT_EQ(ndtom::mapSimilarity(test, GaussianSet{}), 0.0);
  EXPECT_EQ(ndtom::mapSimilarity(GaussianSet{}, reference), 0.0);
}

TEST(MapSimilarity, SingularCovarianceThrowsUnlessFloored) {
  Gaussian planar;
  planar.covariance = Eigen::Vector3d(0.01, 0.02, 0.0).asDiagonal();
  EXPECT_THROW(ndtom::gaussianSimilarity(planar, planar), std::invalid_argument);
  planar.covariance = ndtom::flooredCovariance(planar.covariance, {1e-6});
  EXPECT_EQ(ndtom::gaussianSimilarity(planar, planar), 1.0);
  const Eigen::Vector3d eigenvalues =
      Eigen::SelfAdjointEigenSolver<Matrix3d>(planar.covariance).eigenvalues();
  EXPECT_NEAR(eigenvalues[0], 1e-6, 1e-15);
  EXPECT_NEAR(eigenvalues[2], 0.02, 1e-15);
}

TEST(MapSimilarity, FloorLeavesRegularCovariancesBitForBit) {
  std::mt19937 rng(9);
  for (int i = 0; i < 100; ++i) {
    const Matrix3d c = randomCovariance(rng);  // smallest eigenvalue ≥ 1e-4
    const Matrix3d floored = ndtom::flooredCovariance(c, {1e-6});
    EXPECT_TRUE((floored.array() == c.array()).all());
  }
  EXPECT_THROW(ndtom::flooredCovariance(Matrix3d::Identity(), {0.0}), std::invalid_argument);
}

TEST(MapSimilarity, RecursiveMapMatchesItsBatchMap) {
  // Several scans merged by RCU give the batch Gaussians: similarity 1 up to rounding.
  std::mt19937 rng(10);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  ndtom::MapOptions options;
  options.occupancy.enabled = false;
  ndtom::NdtMap map(options);
  std::vector<Vector3d> all;
  for (int scan = 0; scan < 5; ++scan) {
    std::vector<Vector3d> points;
    for (int i = 0; i < 3000; ++i) points.emplace_back(u(rng), u(rng), 0.02 * u(rng) - 1.0);
    map.insertScan(points, Vector3d(0, 0, 0.5));
    all.insert(all.end(), points.begin(), points.end());
  }
  const GaussianSet batch =
      ndtom::gaussianSetOf(ndtom::batchNdt(all, map.geometry()), map.geometry());
  ASSERT_EQ(batch.size(), map.numGaussians());
  EXPECT_NEAR(ndtom::mapSimilarity(ndtom::gaussianSetOf(map), batch), 1.0, 1e-9);
  // Per-scan variant: a cloud against a map made of that cloud alone.
  ndtom::NdtMap single(options);
  const std::vector<Vector3d> first(all.begin(), all.begin() + 3000);
  single.insertScan(first, Vector3d(0, 0, 0.5));
  EXPECT_NEAR(ndtom::scanSimilarity(first, ndtom::gaussianSetOf(single), single.geometry()), 1.0,
              1e-9);
  EXPECT_LT(ndtom::scanSimilarity(first, ndtom::gaussianSetOf(map), map.geometry()), 0.99);
}

}  // namespace
