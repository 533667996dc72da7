// Multi-resolution (Sec. III-B) and merging: both must equal a batch computation.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "ndtom/map/ndt_map.h"
#include "ndtom_eval/batch_ndt.h"

using Eigen::Vector3d;
using ndtom::CellIndex;
using ndtom::MapOptions;
using ndtom::NdtMap;

namespace {

struct Scan {
  Vector3d origin;
  std::vector<Vector3d> points;
};

// Surfaces and clutter in a 12 m box, including negative coordinates.
std::vector<Scan> randomScans(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Scan> scans(count);
  for (auto& s : scans) {
    s.origin = Vector3d(2 * u(rng), 2 * u(rng), 0.5 * u(rng));
    for (int i = 0; i < 400; ++i) {
      const double a = 6 * u(rng), b = 6 * u(rng);
      switch (i % 4) {
        case 0:
          s.points.emplace_back(5.3 + 0.03 * u(rng), a, 0.5 * b);
          break;
        case 1:
          s.points.emplace_back(a, b, -1.1 + 0.03 * u(rng));
          break;
        case 2:
          s.points.emplace_back(a, -4.7 + 0.05 * u(rng), 0.5 * b);
          break;
        default:
          s.points.emplace_back(0.7 * a, 0.7 * b, 0.3 * u(rng) + 1.0);
          break;
      }
    }
  }
  return scans;
}

std::vector<Vector3d> allPoints(const std::vector<Scan>& scans) {
  std::vector<Vector3d> all;
  for (const auto& s : scans) all.insert(all.end(), s.points.begin(), s.points.end());
  return all;
}

// Every cell of the map has exactly the statistics of the batch, and no other cell has any.
void expectEqualsBatch(const NdtMap& map, const ndtom::CellStatsMap& batch) {
  size_t cells_with_stats = 0;
  map.forEachCell([&](const ndtom::CellView& c) {
    if (!c.stats) return;
    ++cells_with_stats;
    const auto it = batch.find(c.index);
    ASSERT_NE(it, batch.end());
    EXPECT_EQ(c.stats->n, it->second.n);
    EXPECT_LT((c.stats->relative_mean - it->second.relative_mean).norm(), 1e-12);
    EXPECT_LT((c.stats->scatter - it->second.scatter).norm(),
              1e-9 * it->second.scatter.norm() + 1e-15);
  });
  EXPECT_EQ(cells_with_stats, batch.size());
}

}  // namespace

TEST(MultiResolution, CoarseMapEqualsBatchAtCoarseResolution) {
  for (const int factor : {2, 3, 4}) {
    MapOptions o;
    o.resolution = 0.25;
    o.occupancy.enabled = false;
    NdtMap fine(o);
    const auto scans = randomScans(6, 10 + factor);
    for (const auto& s : scans) fine.insertScan(s.points, s.origin);
    const NdtMap coarse = fine.coarsened(factor);
    EXPECT_DOUBLE_EQ(coarse.geometry().resolution(), 0.25 * factor);
    expectEqualsBatch(coarse, ndtom::batchNdt(allPoints(scans), coarse.geometry()));
    EXPECT_LT(coarse.numCells(), fine.numCells());
  }
}

TEST(MultiResolution, CoarseLogOddsIsTheLargestFineLogOdds) {
  MapOptions o;
  o.resolution = 0.2;
  NdtMap fine(o);
  for (const auto& s : randomScans(4, 3)) fine.insertScan(s.points, s.origin);
  const NdtMap coarse = fine.coarsened(3);
  std::map<CellIndex, float> expected;
  fine.forEachCell([&](const ndtom::CellView& c) {
    const CellIndex k{ndtom::floorDiv(c.index.x, 3), ndtom::floorDiv(c.index.y, 3),
                      ndtom::floorDiv(c.index.z, 3)};
    auto [it, inserted] = expected.emplace(k, c.logodds);
    if (!inserted) it->second = std::max(it->second, c.logodds);
  });
  EXPECT_EQ(coarse.numCells(), expected.size());
  for (const auto& [k, l] : expected) {
    const auto c = coarse.cell(k);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->logodds, l);
    EXPECT_EQ(c->stats != nullptr, l > 0) << "statistics exactly where the cell is occupied";
  }
}

TEST(MultiResolution, FactorOneIsACopyAndBadFactorsThrow) {
  NdtMap fine;
  for (const auto& s : randomScans(2, 1)) fine.insertScan(s.points, s.origin);
  const NdtMap same = fine.coarsened(1);
  EXPECT_EQ(same.numCells(), fine.numCells());
  EXPECT_EQ(same.numGaussians(), fine.numGaussians());
  EXPECT_THROW(fine.coarsened(0), std::invalid_argument);
  EXPECT_THROW(fine.coarsened(-2), std::invalid_argument);
}

TEST(Merge, MergedMapsEqualOneMapBuiltFromAllData) {
  MapOptions o;
  o.resolution = 0.3;
  o.occupancy.enabled = false;
  const auto scans = randomScans(8, 77);
  NdtMap a(o), b(o), whole(o);
  for (size_t i = 0; i < scans.size(); ++i) {
    (i % 3 == 0 ? a : b).insertScan(scans[i].points, scans[i].origin);
    whole.insertScan(scans[i].points, scans[i].origin);
  }
  NdtMap merged = a;
  merged.merge(b);
  expectEqualsBatch(merged, ndtom::batchNdt(allPoints(scans), merged.geometry()));
  EXPECT_EQ(merged.numGaussians(), whole.numGaussians());
}

TEST(Merge, LogOddsAddAndClamp) {
  MapOptions o;
  o.resolution = 0.3;
  const auto scans = randomScans(6, 5);
  NdtMap a(o), b(o);
  for (size_t i = 0; i < scans.size(); ++i)
    (i < 3 ? a : b).insertScan(scans[i].points, scans[i].origin);
  NdtMap merged = a;
  merged.merge(b);
  size_t cells_in_either = a.numCells();
  b.forEachCell([&](const ndtom::CellView& cb) {
    const auto ca = a.cell(cb.index);
    if (!ca) ++cells_in_either;
    const double sum = double(cb.logodds) + (ca ? double(ca->logodds) : 0.0);
    const float expected = float(std::clamp(sum, o.occupancy.logodds_min, o.occupancy.logodds_max));
    const auto cm = merged.cell(cb.index);
    ASSERT_TRUE(cm);
    EXPECT_EQ(cm->logodds, expected);
    if (expected <= 0) {
      EXPECT_EQ(cm->stats, nullptr);
    }
  });
  EXPECT_EQ(merged.numCells(), cells_in_either);
}

TEST(Merge, DifferentResolutionsAreRejected) {
  MapOptions fine, coarse;
  fine.resolution = 0.1;
  coarse.resolution = 0.2;
  NdtMap a(fine), b(coarse);
  EXPECT_THROW(a.merge(b), std::invalid_argument);
}

TEST(Merge, MergingWithItselfDoublesTheEvidence) {
  MapOptions o;
  o.occupancy.enabled = false;
  NdtMap a(o);
  for (const auto& s : randomScans(2, 9)) a.insertScan(s.points, s.origin);
  NdtMap doubled = a;
  doubled.merge(doubled);
  a.forEachCell([&](const ndtom::CellView& c) {
    const auto d = doubled.cell(c.index);
    ASSERT_TRUE(d && d->stats);
    EXPECT_EQ(d->stats->n, 2 * c.stats->n);
    EXPECT_LT((d->stats->relative_mean - c.stats->relative_mean).norm(), 1e-15);
  });
}
