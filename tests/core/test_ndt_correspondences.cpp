// Point-to-Gaussian correspondences: against a brute-force search over all Gaussians, and
// as the inner step of an ICP loop (Umeyama) that must recover a known rigid motion.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>

#include "ndtom/matching/ndt_correspondences.h"
#include "synthetic_room.h"

using Eigen::Isometry3d;
using Eigen::Vector3d;
using ndtom::CorrespondenceOptions;
using ndtom::GaussianLookup;
using ndtom::NdtMap;

namespace {

NdtMap roomMap(double resolution) {
  return ndtom::testing::roomMap(resolution, 60000);
}

struct Expected {
  bool found = false;
  ndtom::CellIndex cell;
  Vector3d target;
};

// All Gaussians within the radius, the k nearest by (distance, cell order), the smallest
// Mahalanobis distance among them, then the projection from a direct matrix inverse.
Expected bruteForce(const NdtMap& map, const Vector3d& p, const CorrespondenceOptions& o) {
  struct Candidate {
    double d2;
    ndtom::CellIndex cell;
    ndtom::Gaussian g;
  };
  const double radius = o.max_distance + o.angular_tolerance * (p - o.pivot).norm();
  std::vector<Candidate> all;
  map.forEachGaussian([&](const ndtom::Gaussian& g) {
    const double d2 = (g.mean - p).squaredNorm();
    if (d2 <= radius * radius) all.push_back({d2, g.cell, g});
  });
  std::sort(all.begin(), all.end(), [](const Candidate& a, const Candidate& b) {
    return a.d2 < b.d2 || (a.d2 == b.d2 && a.cell < b.cell);
  });
  if (all.size() > o.max_candidates) all.resize(o.max_candidates);
  Expected best;
  double best_maha = INFINITY;
  for (const Candidate& c : all) {
    const Eigen::Matrix3d inv = c.g.covariance.inverse();
    const double maha = (p - c.g.mean).dot(inv * (p - c.g.mean));
    if (maha < best_maha) {
      best_maha = maha;
      const double lambda_min =
          c.g.covariance.selfadjointView<Eigen::Lower>().eigenvalues().minCoeff();
      best = {true, c.cell, p - lambda_min * inv * (p - c.g.mean)};
    }
  }
  if (best.found && (best.target - p).norm() > radius) best.found = false;
  return best;
}

Isometry3d perturbation(double metres, double degrees) {
  Isometry3d t(Eigen::AngleAxisd(degrees * M_PI / 180, Vector3d(0.3, -0.5, 1).normalized()));
  t.translation() = metres * Vector3d(1, 0.6, -0.4).normalized();
  return t;
}

}  // namespace

TEST(NdtCorrespondences, MatchBruteForce) {
  const NdtMap map = roomMap(0.4);
  const GaussianLookup lookup(map);
  auto scan = ndtom::testing::sampleRoom(700, 5);
  for (auto& p : scan) p = perturbation(0.2, 4) * p;
  scan.push_back(Vector3d(std::nan(""), 0, 0));
  for (const size_t k : {size_t(1), size_t(8)})
    for (const double radius : {0.3, 1.0}) {
      CorrespondenceOptions options;
      options.max_candidates = k;
      options.max_distance = radius;
      if (k == 8) {  // a radius growing with the distance from a pivot
        options.angular_tolerance = 0.05;
        options.pivot = Vector3d(1, -1, 1);
      }
      const auto result = ndtom::findCorrespondences(lookup, scan, options);
      EXPECT_EQ(result.points_considered, scan.size() - 1);
      size_t next = 0, found = 0;
      for (uint32_t i = 0; i + 1 < scan.size(); ++i) {
        const Expected want = bruteForce(map, scan[i], options);
        found += want.found;
        const bool got = next < result.pairs.size() && result.pairs[next].point == i;
        ASSERT_EQ(got, want.found) << "point " << i << " k " << k << " r " << radius;
        if (!got) continue;
        const auto& pair = result.pairs[next++];
        EXPECT_EQ(lookup.meanOwner(pair.gaussian).cell, want.cell);
        EXPECT_LT((pair.target - want.target).norm(), 1e-9);
        EXPECT_NEAR(pair.squared_distance, (pair.target - scan[i]).squaredNorm(), 1e-12);
      }
      EXPECT_EQ(next, result.pairs.size());
      EXPECT_GT(found, scan.size() / 3);
    }
}

TEST(NdtCorrespondences, StrideAndFirstSelectPoints) {
  const NdtMap map = roomMap(0.4);
  const GaussianLookup lookup(map);
  const auto scan = ndtom::testing::sampleRoom(100, 6);
  CorrespondenceOptions options;
  options.first = 2;
  options.stride = 5;
  const auto result = ndtom::findCorrespondences(lookup, scan, options);
  EXPECT_EQ(result.points_considered, 20u);
  for (const auto& pair : result.pairs) EXPECT_EQ(pair.point % 5, 2u);
}

// ICP with these pairs and a point-to-point solver recovers a rigid motion of 0.3 m and 3°.
TEST(NdtCorrespondences, IcpLoopRecoversAKnownMotion) {
  const NdtMap map = roomMap(0.2);
  const GaussianLookup lookup(map);
  const auto local = ndtom::testing::sampleRoom(20000, 7);  // scan in the world frame
  const Isometry3d truth = Isometry3d::Identity();
  Isometry3d estimate = perturbation(0.3, 3);
  CorrespondenceOptions options;
  options.max_distance = 1.0;
  std::vector<Vector3d> moved(local.size());
  for (int iteration = 0; iteration < 60; ++iteration) {
    for (size_t i = 0; i < local.size(); ++i) moved[i] = estimate * local[i];
    const auto result = ndtom::findCorrespondences(lookup, moved, options);
    ASSERT_GT(result.pairs.size(), 1000u);
    Eigen::Matrix3Xd from(3, result.pairs.size()), to(3, result.pairs.size());
    for (size_t j = 0; j < result.pairs.size(); ++j) {
      from.col(j) = local[result.pairs[j].point];
      to.col(j) = result.pairs[j].target;
    }
    estimate.matrix() = Eigen::umeyama(from, to, false);
    if (iteration == 20) options.max_distance = 0.3;
  }
  const Isometry3d error = truth.inverse() * estimate;
  EXPECT_LT(error.translation().norm(), 0.005);
  EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle() * 180 / M_PI, 0.05);
}

TEST(NdtCorrespondences, MatchingRatio) {
  const NdtMap map = roomMap(0.4);
  const GaussianLookup lookup(map);
  auto scan = ndtom::testing::sampleRoom(2000, 8);
  EXPECT_GT(ndtom::matchingRatio(lookup, scan, 3.0), 0.9);
  // Brute force: smallest Mahalanobis distance over the 27 cells around each point.
  size_t matched = 0;
  for (const auto& p : scan) {
    const ndtom::CellIndex home = map.geometry().cellOf(p);
    double best = INFINITY;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
          if (const auto g = map.gaussian({home.x + dx, home.y + dy, home.z + dz}, ndtom::Covariance::Regularized))
            best = std::min(best, (p - g->mean).dot(g->covariance.inverse() * (p - g->mean)));
    matched += best <= 1.0;
  }
  EXPECT_NEAR(ndtom::matchingRatio(lookup, scan, 1.0), double(matched) / scan.size(), 1e-12);
  for (auto& p : scan) p.z() += 50;  // nowhere near the room
  EXPECT_EQ(ndtom::matchingRatio(lookup, scan, 3.0), 0.0);
  EXPECT_EQ(ndtom::matchingRatio(lookup, {}, 3.0), 0.0);
}

TEST(NdtCorrespondences, RejectsBadOptions) {
  const GaussianLookup lookup{NdtMap{}};
  CorrespondenceOptions bad_distance, bad_k, bad_stride, bad_angle, bad_pivot;
  bad_distance.max_distance = 0;
  bad_k.max_candidates = 0;
  bad_stride.stride = 0;
  bad_angle.angular_tolerance = -0.1;
  bad_pivot.pivot.x() = std::nan("");
  for (const auto& o : {bad_distance, bad_k, bad_stride, bad_angle, bad_pivot})
    EXPECT_THROW(ndtom::findCorrespondences(lookup, {}, o), std::invalid_argument);
}
