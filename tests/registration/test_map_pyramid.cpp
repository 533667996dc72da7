// MapPyramid following a map scan by scan (an online mapper's target): after every insertion
// and every move of its region, its levels must be those of a pyramid built anew from the map
// as it is, bit for bit; and the map's record of what an insertion changed must cover every
// cell whose statistics changed (found by comparing copies before and after).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstring>
#include <string>
#include <vector>

#include "core/synthetic_room.h"
#include "ndtom/map/memory_budget.h"
#include "ndtom/registration/map_pyramid.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

using namespace ndtom;
using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace {

const std::string kBalm = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld";
const std::vector<int> kFactors{16, 8, 4, 2, 1};

struct Scan {
  std::vector<Vector3d> points;  // world frame
  Vector3d origin;
};

std::vector<Scan> balmScans(int count) {
  std::vector<Scan> scans;
  const auto poses = io::readPoseFile(kBalm + "/poses.txt");
  for (int i = 0; i < count; ++i) {
    Scan s;
    s.origin = poses[size_t(i)].pose.translation();
    for (const Vector3d& p : io::readPcd(kBalm + "/full" + std::to_string(i) + ".pcd").points)
      if (p.allFinite() && p.norm() > 0.5 && p.norm() < 30)
        s.points.push_back(poses[size_t(i)].pose * p);
    scans.push_back(std::move(s));
  }
  return scans;
}

MapOptions mapOptions() {
  MapOptions o;
  o.resolution = 0.2;
  return o;
}

/// Blocks within `radius` of `centre` (block centres), as a region around a sensor.
MapPyramid::BlockFilter region(const Vector3d& centre, double radius, double resolution) {
  const double edge = kBlockEdge * resolution;
  return [=](const CellIndex& b) {
    const Vector3d middle = (Vector3d(b.x, b.y, b.z) + Vector3d::Constant(0.5)) * edge;
    return (middle - centre).norm() <= radius;
  };
}

std::vector<const PreparedGaussian*> gaussiansOf(const GaussianLookup& lookup) {
  std::vector<const PreparedGaussian*> out;
  lookup.forEachGaussian([&](const PreparedGaussian& g) { out.push_back(&g); });
  return out;
}

bool sameBits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

/// Every level of `got` holds exactly the Gaussians of `want`'s, bit for bit.
void expectSameLevels(const MapPyramid& got, const MapPyramid& want, const std::string& when) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t l = 0; l < got.size(); ++l) {
    const auto a = gaussiansOf(got.level(l)), b = gaussiansOf(want.level(l));
    ASSERT_EQ(a.size(), b.size()) << when << ", level x" << got.factor(l);
    ASSERT_EQ(got.level(l).size(), a.size());
    for (size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a[i]->cell, b[i]->cell) << when << ", level x" << got.factor(l);
      EXPECT_EQ(a[i]->n, b[i]->n);
      EXPECT_TRUE(sameBits(a[i]->mean, b[i]->mean)) << when;
      EXPECT_TRUE(sameBits(a[i]->covariance, b[i]->covariance)) << when;
      EXPECT_TRUE(sameBits(a[i]->information, b[i]->information)) << when;
      EXPECT_EQ(got.level(l).find(a[i]->cell), a[i]);
    }
  }
}

}  // namespace

TEST(MapPyramid, FollowingTheMapGivesTheLevelsOfANewPyramid) {
  const std::vector<Scan> scans = balmScans(6);
  NdtMap map(mapOptions());
  map.insertScan(scans[0].points, scans[0].origin);
  const auto members = region(scans[0].origin, 25, 0.2);
  MapPyramid pyramid(map, kFactors, 1, members);
  for (size_t k = 1; k < scans.size(); ++k) {
    map.insertScan(scans[k].points, scans[k].origin);
    ASSERT_TRUE(pyramid.follow(map)) << "scan " << k;
    EXPECT_EQ(pyramid.revision(), map.revision());
    expectSameLevels(pyramid, MapPyramid(map, kFactors, 1, members), "scan " + std::to_string(k));
  }
  EXPECT_GT(pyramid.level(kFactors.size() - 1).size(), 1000u);
  EXPECT_TRUE(pyramid.follow(map)) << "nothing changed: nothing to do";
}

TEST(MapPyramid, MovingTheRegionGivesThePyramidOfTheNewRegion) {
  const std::vector<Scan> scans = balmScans(4);
  NdtMap map(mapOptions());
  for (const Scan& s : scans) map.insertScan(s.points, s.origin);
  MapPyramid pyramid(map, kFactors, 2, region(scans[0].origin, 15, 0.2));
  for (const double shift : {4.0, 9.0, -20.0}) {
    const auto moved = region(scans[0].origin + Vector3d(shift, 0.5 * shift, 0), 15, 0.2);
    pyramid.setMembers(map, moved);
    expectSameLevels(pyramid, MapPyramid(map, kFactors, 1, moved),
                     "shift " + std::to_string(shift));
  }
  pyramid.setMembers(map, {});
  expectSameLevels(pyramid, MapPyramid(map, kFactors), "the whole map");
}

TEST(MapPyramid, AnyThreadCountBuildsTheSameLevels) {
  const std::vector<Scan> scans = balmScans(3);
  NdtMap map(mapOptions());
  for (const Scan& s : scans) map.insertScan(s.points, s.origin);
  const MapPyramid one(map, kFactors, 1);
  for (const int threads : {2, 5})
    expectSameLevels(MapPyramid(map, kFactors, threads), one, "threads");
}

TEST(MapPyramid, FollowRefusesChangesItCannotAccountFor) {
  const std::vector<Scan> scans = balmScans(4);
  NdtMap map(mapOptions());
  map.insertScan(scans[0].points, scans[0].origin);
  MapPyramid pyramid(map, kFactors);
  const uint64_t at = pyramid.revision();
  // Two insertions since: the last one's record does not start where the pyramid is.
  map.insertScan(scans[1].points, scans[1].origin);
  map.insertScan(scans[2].points, scans[2].origin);
  EXPECT_FALSE(pyramid.follow(map));
  EXPECT_EQ(pyramid.revision(), at) << "unchanged";
  // A change other than an insertion leaves no record.
  MapPyramid fresh(map, kFactors);
  NdtMap other(mapOptions());
  other.insertScan(scans[3].points, scans[3].origin);
  map.merge(other);
  EXPECT_EQ(map.lastStatsChanges().from, 0u);
  EXPECT_FALSE(fresh.follow(map));
  // A copy of the map at the pyramid's revision needs nothing.
  MapPyramid current(map, kFactors);
  const NdtMap copy = map;
  EXPECT_TRUE(current.follow(copy));
  EXPECT_THROW(current.setMembers(other, {}), std::logic_error);
}

TEST(MapPyramid, UpdatesKeepTheMemoryBudget) {
  // A pyramid of a small region of a map whose budget leaves room for little more, then
  // asked for the whole map: refused, the levels unchanged. (follow() and setMembers() redo
  // cells through the same step.)
  const std::vector<Scan> scans = balmScans(2);
  NdtMap roomy(mapOptions());
  for (const Scan& s : scans) roomy.insertScan(s.points, s.origin);
  MapOptions tight = mapOptions();
  tight.scan.memory_budget = roomy.memoryBytes() + (1 << 20);
  NdtMap map(tight);
  roomy.forEachCell([&](const CellView& c) {
    map.setCell(c.index, c.logodds, c.stats ? *c.stats : CellStats{});
  });
  map.shrinkToFit();
  const auto small = region(scans[0].origin, 4, 0.2);
  MapPyramid pyramid(map, kFactors, 1, small);
  ASSERT_GT(pyramid.level(0).size(), 0u);
  try {
    pyramid.setMembers(map, {});
    ADD_FAILURE() << "the whole map's levels within " << tight.scan.memory_budget;
  } catch (const MemoryBudgetError& e) {
    EXPECT_NE(std::string(e.what()).find("registration pyramid"), std::string::npos) << e.what();
  }
  expectSameLevels(pyramid, MapPyramid(map, kFactors, 1, small), "refused");
  // The members stayed: moving the region within them changes nothing.
  pyramid.setMembers(map, small);
  expectSameLevels(pyramid, MapPyramid(map, kFactors, 1, small), "same members");
}

TEST(StatsChanges, CoverEveryCellWhoseStatisticsChanged) {
  const std::vector<Scan> scans = balmScans(5);
  NdtMap map(mapOptions());
  map.insertScan(scans[0].points, scans[0].origin);
  size_t emptied = 0;
  for (size_t k = 1; k < scans.size(); ++k) {
    const NdtMap before = map;
    const uint64_t from = map.revision();
    map.insertScan(scans[k].points, scans[k].origin);
    const StatsChanges& changes = map.lastStatsChanges();
    EXPECT_EQ(changes.from, from);
    EXPECT_EQ(changes.to, map.revision());
    const auto recorded = [&](const CellIndex& cell) {  // in any of the block's entries
      const int i = offsetInBlock(cell);
      for (const BlockCells& b : changes.blocks)
        if (b.block == blockOf(cell) && ((b.cells[size_t(i >> 6)] >> (i & 63)) & 1) != 0)
          return true;
      return false;
    };
    // Brute force: every cell with statistics now or before, compared.
    size_t changed = 0;
    const auto check = [&](const NdtMap& a, const NdtMap& b, const CellView& c) {
      const auto other = b.cell(c.index);
      const CellStats* s = other ? other->stats : nullptr;
      const bool same = s && s->n == c.stats->n &&
                        sameBits(s->relative_mean, c.stats->relative_mean) &&
                        sameBits(s->scatter, c.stats->scatter);
      if (same) return;
      changed += &a == &map;
      emptied += &a == &before && !s;
      EXPECT_TRUE(recorded(c.index))
          << "scan " << k << ": cell " << c.index.x << " " << c.index.y << " " << c.index.z;
    };
    map.forEachCell([&](const CellView& c) {
      if (c.stats) check(map, before, c);
    });
    before.forEachCell([&](const CellView& c) {
      if (c.stats) check(before, map, c);
    });
    EXPECT_GT(changed, 100u) << "scan " << k;
  }
  EXPECT_GT(emptied, 0u) << "rays emptied some cells";
  // Anything but an insertion leaves the changes unknown.
  map.setCell({0, 0, 0}, 1.f, CellStats{});
  EXPECT_EQ(map.lastStatsChanges().from, 0u);
}
