// NDT point-to-distribution likelihood: against a brute-force sum that inverts each cell's
// covariance directly, and its peak at the pose the scan was taken from.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>

#include "ndtom/matching/ndt_likelihood.h"
#include "synthetic_room.h"

using Eigen::Vector3d;
using ndtom::GaussianLookup;
using ndtom::LikelihoodOptions;
using ndtom::NdtMap;

namespace {

NdtMap roomMap() {
  return ndtom::testing::roomMap(0.4, 60000);
}

// Σ_p log((1 − c)·max over cells within one step of p's cell of exp(−½ d²) + c).
double bruteForce(const NdtMap& map, const std::vector<Vector3d>& points, double c,
                  bool neighbours) {
  double sum = 0;
  for (const Vector3d& p : points) {
    if (!p.allFinite()) continue;
    const ndtom::CellIndex home = map.geometry().cellOf(p);
    double best = 0;
    const int reach = neighbours ? 1 : 0;
    for (int dx = -reach; dx <= reach; ++dx)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dz = -reach; dz <= reach; ++dz) {
          const auto g = map.gaussian({home.x + dx, home.y + dy, home.z + dz}, ndtom::Covariance::Regularized);
          if (!g) continue;
          const Vector3d d = p - g->mean;
          best = std::max(best, std::exp(-0.5 * d.dot(g->covariance.inverse() * d)));
        }
    sum += std::log((1 - c) * best + c);
  }
  return sum;
}

}  // namespace

TEST(NdtLikelihood, MatchesBruteForce) {
  const NdtMap map = roomMap();
  const GaussianLookup lookup(map);
  auto scan = ndtom::testing::sampleRoom(3000, 2);
  scan.push_back(Vector3d(std::nan(""), 0, 0));  // skipped
  scan.push_back(Vector3d(40, 40, 40));          // far from everything: the floor only
  for (const bool neighbours : {true, false})
    for (const double c : {0.01, 0.2}) {
      LikelihoodOptions options;
      options.outlier_likelihood = c;
      options.search_neighbours = neighbours;
      const auto result = ndtom::scanLikelihood(lookup, scan, options);
      const double expected = bruteForce(map, scan, c, neighbours);
      EXPECT_NEAR(result.log_likelihood, expected, 1e-9 * std::abs(expected));
      EXPECT_EQ(result.points_scored, scan.size() - 1);
      EXPECT_GT(result.points_matched, scan.size() / 2);
      EXPECT_LT(result.points_matched, scan.size() - 1);
    }
}

TEST(NdtLikelihood, EmptyMapGivesTheOutlierFloorForEveryPoint) {
  const GaussianLookup lookup{NdtMap{}};
  const auto scan = ndtom::testing::sampleRoom(100, 3);
  const auto result = ndtom::scanLikelihood(lookup, scan, LikelihoodOptions{});
  EXPECT_NEAR(result.log_likelihood, 100 * std::log(0.05), 1e-9);
  EXPECT_EQ(result.points_matched, 0u);
  EXPECT_EQ(ndtom::scanLikelihood(lookup, {}, LikelihoodOptions{}).log_likelihood, 0.0);
}

TEST(NdtLikelihood, PeaksAtThePoseTheScanWasTakenFrom) {
  const NdtMap map = roomMap();
  const GaussianLookup lookup(map);
  const auto scan = ndtom::testing::sampleRoom(4000, 4);
  const double at_truth = ndtom::scanLikelihood(lookup, scan, {}).log_likelihood;
  const double deg = M_PI / 180;
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {-1.0, 1.0}) {
      Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
      shift.translation()[axis] = 0.1 * sign;
      Eigen::Isometry3d turn(Eigen::AngleAxisd(2 * deg * sign, Vector3d::Unit(axis)));
      turn.pretranslate(ndtom::testing::kRoomSensor).translate(-ndtom::testing::kRoomSensor);
      for (const auto& moved : {shift, turn}) {
        std::vector<Vector3d> moved_scan;
        for (const auto& p : scan) moved_scan.push_back(moved * p);
        EXPECT_LT(ndtom::scanLikelihood(lookup, moved_scan, {}).log_likelihood, at_truth)
            << "axis " << axis << " sign " << sign;
      }
    }
}

TEST(NdtLikelihood, RejectsBadOptions) {
  const GaussianLookup lookup{NdtMap{}};
  for (const double c : {0.0, 1.0, -0.5, std::nan("")}) {
    LikelihoodOptions options;
    options.outlier_likelihood = c;
    EXPECT_THROW(ndtom::scanLikelihood(lookup, {}, options), std::invalid_argument) << c;
  }
}
