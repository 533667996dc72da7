// The shares of a scan's points the processes of a distributed build walk (point_shares.h):
// they cover the points in order, and their walks, counted by inserting each share alone,
// are about equal where equal counts of points are not.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <vector>

#include "insertion/point_shares.h"
#include "ndtom/map/ndt_map.h"
#include "support/lidar_scans.h"

namespace {

ndtom::MapOptions mapOptions() {
  ndtom::MapOptions o;
  o.resolution = 0.4;
  o.scan.max_range = 30;
  return o;
}

std::vector<std::pair<size_t, size_t>> shares(const ndtom::ScanContext& scan,
                                              const std::vector<Eigen::Vector3d>& points,
                                              size_t ranks) {
  std::vector<std::pair<size_t, size_t>> out;
  for (size_t r = 0; r < ranks; ++r)
    out.push_back(ndtom::pointShare(scan, points.data(), points.size(), ranks, r));
  return out;
}

// The cells the serial walk visits for points [first, last): an independent count.
size_t visitsOf(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& origin,
                size_t first, size_t last) {
  ndtom::NdtMap map(mapOptions());
  const std::vector<Eigen::Vector3d> share(points.begin() + std::ptrdiff_t(first),
                                           points.begin() + std::ptrdiff_t(last));
  return map.insertScan(share, origin).voxel_visits;
}

// Slowest share's walk over the mean share's.
double imbalance(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& origin,
                 const std::vector<std::pair<size_t, size_t>>& parts) {
  size_t slowest = 0, all = 0;
  for (const auto& [first, last] : parts) {
    const size_t v = visitsOf(points, origin, first, last);
    slowest = std::max(slowest, v);
    all += v;
  }
  return double(slowest) * double(parts.size()) / double(all);
}

}  // namespace

TEST(PointShares, CoverThePointsInOrder) {
  const ndtom::MapOptions o = mapOptions();
  const ndtom::GridGeometry geometry(o.resolution);
  ndtom::WorkerPool pool;
  const Eigen::Vector3d origin(0.3, -0.2, 1.0);
  const ndtom::ScanContext scan{geometry, o.scan, origin, pool};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const size_t n : {0, 1, 15, 16, 17, 1000}) {
    std::vector<Eigen::Vector3d> points;
    for (size_t i = 0; i < n; ++i)  // lengths from 0 to 40 m, and some not points
      points.push_back(i % 7 == 3 ? Eigen::Vector3d(nan, 0, 0)
                                  : origin + Eigen::Vector3d(0.04 * double(i % 1000), 1, 0));
    for (size_t ranks = 1; ranks <= 20; ++ranks) {
      SCOPED_TRACE(testing::Message() << n << " points, " << ranks << " processes");
      const auto parts = shares(scan, points, ranks);
      EXPECT_EQ(parts.front().first, 0u);
      EXPECT_EQ(parts.back().second, n);
      for (size_t r = 0; r < ranks; ++r) {
        EXPECT_LE(parts[r].first, parts[r].second);
        if (r > 0) {
          EXPECT_EQ(parts[r].first, parts[r - 1].second);
        }
      }
    }
  }
}

TEST(PointShares, WalkAboutEqualCellsWhereEqualCountsOfPointsDoNot) {
  const ndtom::MapOptions o = mapOptions();
  const ndtom::GridGeometry geometry(o.resolution);
  ndtom::WorkerPool pool;
  // Half the rays 2 m long, half 25 m: equal counts give one process 12 times the other's
  // walk. Half 20 m, half 300 m: walked only to max_range (30 m), which the shares must know.
  const Eigen::Vector3d origin(0.1, 0.1, 0.1);
  const ndtom::ScanContext scan{geometry, o.scan, origin, pool};
  for (const auto& [near, far] : {std::pair{2.0, 25.0}, std::pair{20.0, 300.0}}) {
    SCOPED_TRACE(testing::Message() << "points at " << near << " and " << far << " m");
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < 4000; ++i) {
      const double angle = 0.001 * i, range = i < 2000 ? near : far;
      points.push_back(origin + range * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.1));
    }
    if (near == 2.0) {
      EXPECT_GT(imbalance(points, origin, {{0, 2000}, {2000, 4000}}), 1.8);
    }
    EXPECT_LT(imbalance(points, origin, shares(scan, points, 2)), 1.1);
  }

  // Real scans (a lidar's fans, near and far).
  for (const auto& s : ndtom::testing::lidarScansInWorld(2)) {
    const ndtom::ScanContext real{geometry, o.scan, s.origin, pool};
    for (const size_t ranks : {2, 4, 16}) {
      SCOPED_TRACE(testing::Message() << ranks << " processes");
      // Equal counts: 1.06, 1.22, 1.34. What is left at 16: the cost of a point besides its
      // walk, which the shares count and the visits do not.
      EXPECT_LT(imbalance(s.points, s.origin, shares(real, s.points, ranks)),
                ranks < 16 ? 1.1 : 1.2);
    }
  }
}
