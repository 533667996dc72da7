// A block packs the statistics of its cells that have some: cells of one block gain and lose
// them in random order (hits, free rays, setCell), checked against a std::map reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <utility>

#include "ndtom/files/map_io.h"
#include "ndtom/map/ndt_map.h"
#include "support/brute_force.h"

using Eigen::Vector3d;
using ndtom::CellIndex;
using ndtom::CellStats;
using ndtom::MapOptions;
using ndtom::NdtMap;

namespace {

struct RefCell {
  float logodds = 0;
  CellStats stats;  ///< n == 0: none
};

// Eq. 12 and the RCU merge per cell, with rays found by brute force: the map's semantics
// without its storage.
class Reference {
 public:
  explicit Reference(const MapOptions& o) : o_(o), geometry_(o.resolution) {}

  void insert(const std::vector<Vector3d>& points, const Vector3d& origin) {
    std::map<CellIndex, std::vector<Vector3d>> hits;  // points relative to the cell centre
    std::map<CellIndex, int> misses;
    for (const Vector3d& p : points) {
      const CellIndex c = geometry_.cellOf(p);
      hits[c].push_back(p - geometry_.cellCenter(c));
      for (const CellIndex& m : ndtom::testing::bruteForce(geometry_, origin, p)) ++misses[m];
    }
    for (const auto& [c, relative] : hits)
      update(c, double(relative.size()) * o_.occupancy.hitLogOdds(),
             CellStats::fromPoints(relative));
    for (const auto& [c, n] : misses)
      if (!hits.count(c)) update(c, n * o_.occupancy.missLogOdds(), CellStats{});
  }

  void set(const CellIndex& c, float logodds, const CellStats& stats) {
    cells_[c] = {clamp(logodds), stats};
  }

  const std::map<CellIndex, RefCell>& cells() const { return cells_; }

 private:
  float clamp(double l) const {
    return float(std::clamp(l, o_.occupancy.logodds_min, o_.occupancy.logodds_max));
  }
  void update(const CellIndex& c, double delta, const CellStats& scan) {
    RefCell& cell = cells_[c];
    cell.logodds = clamp(double(cell.logodds) + delta);
    if (cell.logodds <= 0.f)
      cell.stats = CellStats{};
    else
      cell.stats.merge(scan);
  }

  MapOptions o_;
  ndtom::GridGeometry geometry_;
  std::map<CellIndex, RefCell> cells_;
};

void expectSameCells(const NdtMap& map, const Reference& ref) {
  ASSERT_EQ(map.numCells(), ref.cells().size());
  for (const auto& [index, expected] : ref.cells()) {
    const auto cell = map.cell(index);
    ASSERT_TRUE(cell.has_value());
    ASSERT_EQ(cell->logodds, expected.logodds) << index.x << "," << index.y << "," << index.z;
    if (expected.stats.empty()) {
      ASSERT_EQ(cell->stats, nullptr) << index.x << "," << index.y << "," << index.z;
      continue;
    }
    ASSERT_NE(cell->stats, nullptr) << index.x << "," << index.y << "," << index.z;
    ASSERT_EQ(cell->stats->n, expected.stats.n);
    ASSERT_LT((cell->stats->relative_mean - expected.stats.relative_mean).norm(), 1e-12);
    ASSERT_LT((cell->stats->scatter - expected.stats.scatter).norm(),
              1e-12 * (1 + expected.stats.scatter.norm()));
  }
  // Iteration walks the packed statistics with the cells: the same pointers as cell().
  size_t visited = 0, with_stats = 0;
  std::set<CellIndex> blocks;
  map.forEachCell([&](const ndtom::CellView& c) {
    ++visited;
    with_stats += c.stats != nullptr;
    blocks.insert(ndtom::blockOf(c.index));
    EXPECT_EQ(c.stats, map.cell(c.index)->stats);
  });
  EXPECT_EQ(visited, ref.cells().size());
  // A lower bound that catches statistics or log-odds left uncounted.
  EXPECT_GE(map.memoryBytes(),
            with_stats * sizeof(CellStats) + blocks.size() * ndtom::kBlockCells * sizeof(float));
}

}  // namespace

TEST(BlockStats, CellsGainAndLoseStatisticsInAnyOrder) {
  MapOptions o;
  o.resolution = 1.0;
  // Strong updates, so that cells flip between occupied and free within a few scans.
  o.occupancy.p_hit = 0.7;
  o.occupancy.p_miss = 0.3;
  NdtMap map(o);
  Reference ref(o);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> coord(0, ndtom::kBlockEdge - 1);  // all in block (0,0,0)
  auto randomCell = [&] { return CellIndex{coord(rng), coord(rng), coord(rng)}; };
  auto pointIn = [&](const CellIndex& c) {
    return Vector3d(c.x + 0.05 + 0.9 * u(rng), c.y + 0.05 + 0.9 * u(rng),
                    c.z + 0.05 + 0.9 * u(rng));
  };

  size_t gained = 0, regained = 0, lost_to_rays = 0, lost_to_hits = 0, refused = 0;
  std::set<CellIndex> ever_had;
  std::optional<CellIndex> last_set;
  for (int step = 0; step < 300; ++step) {
    std::map<CellIndex, RefCell> before = ref.cells();
    std::set<CellIndex> hit;
    size_t gaussians_gained = 0, gaussians_lost = 0;
    if (step % 4 == 3) {
      // setCell adds, replaces or removes statistics. It refuses them in a cell with log-odds
      // <= 0 (the rule of cell_rules.h, which the loader applies too), leaving the map as it
      // was; the cell is then set without them.
      const CellIndex c = randomCell();
      const float logodds = float(-2.0 + 3.5 * u(rng));
      std::vector<Vector3d> relative;
      for (int k = int(4 * u(rng)); k > 0; --k)
        relative.push_back(pointIn(c) - Vector3d(c.x + 0.5, c.y + 0.5, c.z + 0.5));
      CellStats stats = CellStats::fromPoints(relative);
      if (logodds <= 0.f && !stats.empty()) {
        const auto unchanged = ndtom::encodeMap(map);
        EXPECT_THROW(map.setCell(c, logodds, stats), std::invalid_argument);
        EXPECT_EQ(ndtom::encodeMap(map), unchanged);
        stats = CellStats{};
        ++refused;
      }
      map.setCell(c, logodds, stats);
      ref.set(c, logodds, stats);
      last_set = c;
    } else {
      const Vector3d origin = pointIn(randomCell());
      std::vector<Vector3d> points;
      if (last_set && u(rng) < 0.5) {  // one hit: too little to lift log-odds below -0.85
        hit.insert(*last_set);
        points.push_back(pointIn(*last_set));
      }
      last_set.reset();
      for (int k = 1 + int(5 * u(rng)); k > 0; --k) {
        const CellIndex c = randomCell();
        hit.insert(c);
        for (int p = 1 + int(3 * u(rng)); p > 0; --p) points.push_back(pointIn(c));
      }
      const auto report = map.insertScan(points, origin);
      ASSERT_EQ(report.hits, points.size());
      ref.insert(points, origin);
      gaussians_gained = report.gaussians_gained;
      gaussians_lost = report.gaussians_lost;
    }
    expectSameCells(map, ref);
    if (HasFatalFailure()) return;
    // memoryBytes() keeps count as statistics come and go (the memory budget reads it).
    ASSERT_EQ(map.memoryBytes(), map.memoryBytesCounted()) << "step " << step;

    size_t expected_gained = 0, expected_lost = 0;
    for (const auto& [c, now] : ref.cells()) {
      const auto old = before.find(c);
      const CellStats none;
      const CellStats& was = old == before.end() ? none : old->second.stats;
      if (step % 4 != 3) {
        expected_gained += !was.hasGaussian() && now.stats.hasGaussian();
        expected_lost += was.hasGaussian() && !now.stats.hasGaussian();
      }
      if (was.empty() && !now.stats.empty()) {
        ++gained;
        regained += ever_had.count(c);
        ever_had.insert(c);
      }
      if (!was.empty() && now.stats.empty() && step % 4 != 3)
        ++(hit.count(c) ? lost_to_hits : lost_to_rays);
    }
    EXPECT_EQ(gaussians_gained, expected_gained) << "step " << step;
    EXPECT_EQ(gaussians_lost, expected_lost) << "step " << step;
  }
  // The sequence did exercise every way in and out of the packed statistics.
  EXPECT_GT(gained, 200u);
  EXPECT_GT(regained, 40u);
  EXPECT_GT(lost_to_rays, 100u);
  EXPECT_GT(refused, 5u);
  // No cell holds statistics with log-odds <= 0, so a hit (which raises it) never drops any.
  EXPECT_EQ(lost_to_hits, 0u);
  // Copies count their own (tight) statistics arrays.
  const NdtMap copy = map;
  NdtMap assigned;
  assigned = map;
  for (const NdtMap* m : {&copy, &std::as_const(assigned)})
    EXPECT_EQ(m->memoryBytes(), m->memoryBytesCounted());
}
