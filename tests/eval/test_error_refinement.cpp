// Error Refinement baseline: the update equations against numbers worked out by hand, and
// the map's bookkeeping (first Gaussian, occupancy per Eq. 12) against a step-by-step oracle.
#include <gtest/gtest.h>

#include <cmath>

#include "ndtom_eval/error_refinement.h"

using Eigen::Matrix3d;
using Eigen::Vector3d;
using ndtom::ErrorRefinementMap;
using ndtom::ErrorRefinementOptions;

namespace {

const double kHit = std::log(0.6 / 0.4);
const double kMiss = std::log(0.49 / 0.51);

TEST(ErrorRefinement, RateFollowsTheLinearSchedule) {
  const ErrorRefinementOptions o;
  EXPECT_DOUBLE_EQ(ndtom::errorRefinementRate(-10.0, o), 5e-2);
  EXPECT_DOUBLE_EQ(ndtom::errorRefinementRate(10.0, o), 5e-4);
  EXPECT_DOUBLE_EQ(ndtom::errorRefinementRate(0.0, o), 0.5 * (5e-2 + 5e-4));
  EXPECT_DOUBLE_EQ(ndtom::errorRefinementRate(5.0, o), 5e-2 - 0.75 * (5e-2 - 5e-4));
  EXPECT_DOUBLE_EQ(ndtom::errorRefinementRate(50.0, o), 5e-4);   // clamped to +o_max
  EXPECT_DOUBLE_EQ(ndtom::errorRefinementRate(-50.0, o), 5e-2);  // clamped to −o_max
}

TEST(ErrorRefinement, ThreePointsByHand) {
  // μ0 = 0, P0 = 0.01·I, ε = 0.1; x = (1,0,0), (0,1,0), (0,0,2). Worked out on paper:
  // μ1 = (0.1,0,0), d = (0.9,0,0): P1 = diag(0.09, 0.009, 0.009)
  // μ2 = (0.09,0.1,0), d = (−0.09,0.9,0): P2 = [0.08181 −0.0081 0; −0.0081 0.0891 0; 0 0 0.0081]
  // μ3 = (0.081,0.09,0.2), d = (−0.081,−0.09,1.8):
  //   P3 = [0.0742851 −0.006561 −0.01458; −0.006561 0.081 −0.0162; −0.01458 −0.0162 0.33129]
  Vector3d mean = Vector3d::Zero();
  Matrix3d cov = 0.01 * Matrix3d::Identity();
  ndtom::refineGaussian(mean, cov, Vector3d(1, 0, 0), 0.1);
  EXPECT_TRUE(mean.isApprox(Vector3d(0.1, 0, 0), 1e-14));
  EXPECT_TRUE(cov.isApprox(Vector3d(0.09, 0.009, 0.009).asDiagonal().toDenseMatrix(), 1e-14));
  ndtom::refineGaussian(mean, cov, Vector3d(0, 1, 0), 0.1);
  Matrix3d p2;
  p2 << 0.08181, -0.0081, 0, -0.0081, 0.0891, 0, 0, 0, 0.0081;
  EXPECT_TRUE(mean.isApprox(Vector3d(0.09, 0.1, 0), 1e-14));
  EXPECT_TRUE(cov.isApprox(p2, 1e-14));
  ndtom::refineGaussian(mean, cov, Vector3d(0, 0, 2), 0.1);
  Matrix3d p3;
  p3 << 0.0742851, -0.006561, -0.01458, -0.006561, 0.081, -0.0162, -0.01458, -0.0162, 0.33129;
  EXPECT_TRUE(mean.isApprox(Vector3d(0.081, 0.09, 0.2), 1e-14));
  EXPECT_TRUE(cov.isApprox(p3, 1e-13));
}

// Batch mean and unbiased covariance, written out (Eq. 1).
void batch(const std::vector<Vector3d>& x, Vector3d& mean, Matrix3d& cov) {
  mean.setZero();
  for (const auto& p : x) mean += p;
  mean /= double(x.size());
  cov.setZero();
  for (const auto& p : x) cov += (p - mean) * (p - mean).transpose();
  cov /= double(x.size() - 1);
}

TEST(ErrorRefinement, MapFollowsTheEquationsScanByScan) {
  // One cell [0,1)³ at 1 m; sensor straight below so rays cross no other Gaussian.
  ErrorRefinementOptions o;
  o.resolution = 1.0;
  ErrorRefinementMap map(o);
  const Vector3d origin(0.5, 0.5, -5.0);
  const std::vector<Vector3d> first = {{0.2, 0.3, 0.4}, {0.7, 0.1, 0.5}, {0.4, 0.8, 0.6}};
  map.insertScan(first, origin);
  Vector3d mean;
  Matrix3d cov;
  batch(first, mean, cov);  // the first Gaussian is the batch estimate of its first points
  double occ = 3 * kHit;
  const ndtom::CellIndex cell{0, 0, 0};
  ASSERT_TRUE(map.gaussian(cell));
  EXPECT_TRUE(map.gaussian(cell)->mean.isApprox(mean, 1e-14));
  EXPECT_NEAR(*map.occupancy(cell), occ, 1e-12);

  uint32_t n = 3;
  for (const Vector3d& x :
       {Vector3d(0.9, 0.9, 0.1), Vector3d(0.1, 0.5, 0.9), Vector3d(0.5, 0.2, 0.3)}) {
    map.insertScan({x}, origin);
    ++n;
    const double eps = ((5e-4 - 5e-2) / 20.0) * (occ + 10.0) + 5e-2;
    mean = mean + eps * (x - mean);
    cov = cov + eps * ((x - mean) * (x - mean).transpose() - cov);
    occ += kHit;
    const auto g = map.gaussian(cell);
    ASSERT_TRUE(g);
    EXPECT_TRUE(g->mean.isApprox(mean, 1e-14));
    EXPECT_TRUE(g->covariance.isApprox(cov, 1e-13));
    EXPECT_NEAR(*map.occupancy(cell), occ, 1e-12);
    EXPECT_EQ(g->n, n);
  }
}

TEST(ErrorRefinement, FirstGaussianWaitsForThreePoints) {
  ErrorRefinementOptions o;
  o.resolution = 1.0;
  ErrorRefinementMap map(o);
  const Vector3d origin(0.5, 0.5, -5.0);
  const std::vector<Vector3d> a = {{0.1, 0.1, 0.1}, {0.9, 0.2, 0.3}};
  const std::vector<Vector3d> b = {{0.3, 0.8, 0.7}, {0.6, 0.4, 0.9}};
  map.insertScan(a, origin);
  EXPECT_EQ(map.numGaussians(), 0u);
  EXPECT_FALSE(map.occupancy({0, 0, 0}));
  map.insertScan(b, origin);
  ASSERT_EQ(map.numGaussians(), 1u);
  Vector3d mean;
  Matrix3d cov;
  batch({a[0], a[1], b[0], b[1]}, mean, cov);
  const auto g = map.gaussian({0, 0, 0});
  EXPECT_TRUE(g->mean.isApprox(mean, 1e-14));
  EXPECT_TRUE(g->covariance.isApprox(cov, 1e-13));
  EXPECT_NEAR(*map.occupancy({0, 0, 0}), 2 * kHit, 1e-12);  // only the birth scan's hits
}

TEST(ErrorRefinement, FreeRaysLowerOccupancyAndRaiseTheRate) {
  // A Gaussian in cell (0,0,0); then 7 rays from below through it to points in cell (0,0,3).
  ErrorRefinementOptions o;
  o.resolution = 1.0;
  ErrorRefinementMap map(o);
  map.insertScan({{0.5, 0.5, 0.5}, {0.4, 0.6, 0.5}, {0.6, 0.4, 0.6}}, Vector3d(0.5, 0.5, -5.0));
  const double before = *map.occupancy({0, 0, 0});
  std::vector<Vector3d> far(7, Vector3d(0.5, 0.5, 3.5));
  map.insertScan(far, Vector3d(0.5, 0.5, -5.0));
  EXPECT_NEAR(*map.occupancy({0, 0, 0}), before + 7 * kMiss, 1e-12);
  // A scan that both hits the cell and sends rays through it takes the hit update only.
  std::vector<Vector3d> mixed = far;
  mixed.push_back(Vector3d(0.5, 0.5, 0.4));
  const double occ = *map.occupancy({0, 0, 0});
  map.insertScan(mixed, Vector3d(0.5, 0.5, -5.0));
  EXPECT_NEAR(*map.occupancy({0, 0, 0}), occ + kHit, 1e-12);
}

TEST(ErrorRefinement, OccupancyIsClampedAtOMax) {
  ErrorRefinementOptions o;
  o.resolution = 1.0;
  ErrorRefinementMap map(o);
  std::vector<Vector3d> many(100, Vector3d(0.5, 0.5, 0.5));
  many[1].x() = 0.4;
  many[2].y() = 0.4;
  map.insertScan(many, Vector3d(0.5, 0.5, -5.0));
  EXPECT_EQ(*map.occupancy({0, 0, 0}), 10.0);
}

TEST(ErrorRefinement, RejectsBadInput) {
  ErrorRefinementOptions bad;
  bad.e_min = 0;
  EXPECT_THROW(ErrorRefinementMap{bad}, std::invalid_argument);
  bad = {};
  bad.o_max = -1;
  EXPECT_THROW(ErrorRefinementMap{bad}, std::invalid_argument);
  ErrorRefinementMap map;
  EXPECT_THROW(map.insertScan({}, Vector3d(NAN, 0, 0)), std::invalid_argument);
  const auto report =
      map.insertScan({Vector3d(NAN, 0, 0), Vector3d(1, 1, 1), Vector3d(0, 0, 0)}, Vector3d::Zero());
  EXPECT_EQ(report.points_rejected, 2u);  // NaN, and the point at the sensor
  EXPECT_EQ(report.points_used, 1u);
}

}  // namespace
