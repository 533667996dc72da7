// sortRayEnds and groupEnds (src/insertion/) for a distributed build's process with per-point
// rays: only the hits ending in its tiles are sorted and grouped. Checked against an oracle
// computed from the raw points (range test, floor, std::map per cell) and against the serial
// grouping restricted to those tiles: the same groups, in the same order, with the same ends.
#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "insertion/classify_points.h"
#include "insertion/end_groups.h"
#include "insertion/ray_ends.h"
#include "support/lidar_scans.h"

using ndtom::CellIndex;

namespace {

struct Grouping {
  ndtom::ClassifiedPoints points;
  ndtom::SortedRayEnds sorted;
  ndtom::EndGroups groups;
  ndtom::InsertionReport report;
};

void group(const ndtom::ScanContext& scan, const std::vector<Eigen::Vector3d>& points,
           const ndtom::TileOwnership* hits_in, Grouping& out) {
  ndtom::classifyPoints(scan, points, out.points, out.report);
  ndtom::sortRayEnds(scan, out.points, hits_in, out.sorted);
  ndtom::groupEnds(scan, out.points, out.sorted, ndtom::GroupMeans::Skip, out.groups, out.report);
}

// A process's sorted and grouped hits against the oracle and the serial grouping `serial`.
void expectProcessGrouping(const ndtom::ScanContext& scan,
                           const std::vector<Eigen::Vector3d>& points,
                           const ndtom::TileOwnership& owned, const Grouping& serial) {
  const ndtom::GridGeometry& geometry = scan.geometry;
  const ndtom::ScanOptions& options = scan.options;
  // The oracle: each owned hit cell's points in input order, from the raw points.
  std::map<CellIndex, std::vector<Eigen::Vector3d>> oracle;
  for (const Eigen::Vector3d& p : points) {
    const double range = (p - scan.origin).norm();
    if (!p.allFinite() || range == 0 || range < options.min_range || range > options.max_range)
      continue;
    const CellIndex c = geometry.cellOf(p);
    if (owned.ownsBlock(ndtom::blockOf(c))) oracle[c].push_back(p);
  }
  ASSERT_GT(oracle.size(), 100u);

  Grouping part;
  group(scan, points, &owned, part);
  const auto& groups = part.groups.groups;
  ASSERT_EQ(groups.size(), oracle.size());
  EXPECT_EQ(part.report.cells_hit, oracle.size());
  // The serial groups restricted to the owned hit cells, in their order.
  std::vector<const ndtom::EndGroup*> restricted;
  for (const ndtom::EndGroup& g : serial.groups.groups)
    if (g.hit && owned.ownsBlock(ndtom::blockOf(g.cell))) restricted.push_back(&g);
  ASSERT_EQ(restricted.size(), groups.size());
  for (size_t k = 0; k < groups.size(); ++k) {
    const ndtom::EndGroup& g = groups[k];
    const ndtom::EndGroup& r = *restricted[k];
    ASSERT_TRUE(g.hit);
    ASSERT_EQ(g.cell, r.cell) << "group " << k;
    ASSERT_EQ(g.count, r.count) << "group " << k;
    const auto it = oracle.find(g.cell);
    ASSERT_NE(it, oracle.end()) << "group " << k;
    ASSERT_EQ(size_t(g.count), it->second.size()) << "group " << k;
    for (uint32_t i = 0; i < g.count; ++i) {
      ASSERT_EQ(part.groups.sorted_ends[g.begin + i], it->second[i]) << "group " << k;
      ASSERT_EQ(part.groups.sorted_ends[g.begin + i], serial.groups.sorted_ends[r.begin + i]);
    }
  }
  // The hit blocks: the serial ones in owned tiles, with the same cells.
  std::vector<std::pair<CellIndex, ndtom::MapBlock::Mask>> serial_blocks, part_blocks;
  for (const ndtom::HitBlock& h : serial.groups.hit_blocks)
    if (owned.ownsBlock(ndtom::blockOf(serial.groups.blockCell(h))))
      serial_blocks.emplace_back(ndtom::blockOf(serial.groups.blockCell(h)), h.hits);
  for (const ndtom::HitBlock& h : part.groups.hit_blocks)
    part_blocks.emplace_back(ndtom::blockOf(part.groups.blockCell(h)), h.hits);
  EXPECT_EQ(part_blocks, serial_blocks);
}

}  // namespace

TEST(RayEnds, AProcessGroupsExactlyTheHitsInItsTilesAsTheSerialGroupingDoes) {
  const auto scans = ndtom::testing::lidarScansInWorld(2);
  ndtom::WorkerPool pool;
  for (const double resolution : {0.2, 0.3}) {
    const ndtom::GridGeometry geometry(resolution);
    ndtom::ScanOptions options;
    options.max_range = 12;  // truncated rays too: those must not be grouped
    for (const int threads : {1, 2}) {
      options.threads = threads;
      for (const auto& s : scans) {
        const ndtom::ScanContext scan{geometry, options, s.origin, pool};
        Grouping serial;
        group(scan, s.points, nullptr, serial);
        ASSERT_GT(serial.report.truncated, 1000u);
        for (const ndtom::TileOwnership owned :
             {ndtom::TileOwnership{1, 0, 2}, ndtom::TileOwnership{1, 1, 2},
              ndtom::TileOwnership{2, 1, 3}, ndtom::TileOwnership{3, 2, 3}}) {
          SCOPED_TRACE(testing::Message()
                       << "resolution " << resolution << ", " << threads << " threads, tiles of "
                       << owned.tile_blocks << " blocks, rank " << owned.rank << " of "
                       << owned.ranks);
          expectProcessGrouping(scan, s.points, owned, serial);
        }
      }
    }
  }
}

// Ends spread over more blocks than the per-scan table of block owners holds (km apart): the
// hits are then tested tile by tile, with the same result.
TEST(RayEnds, AProcessGroupsItsHitsWhenTheEndsSpanMoreBlocksThanTheTableHolds) {
  const auto scans = ndtom::testing::lidarScansInWorld(1);
  ndtom::WorkerPool pool;
  const ndtom::GridGeometry geometry(0.2);
  ndtom::ScanOptions options;
  options.max_range = 5000;
  options.threads = 1;
  std::vector<Eigen::Vector3d> points = scans[0].points;
  const Eigen::Vector3d o = scans[0].origin;
  for (const double d : {-1500.0, 1500.0})  // a box of ~1900 x 1900 blocks: over 2^20
    for (int k = 0; k < 40; ++k) points.push_back(o + Eigen::Vector3d(d, -d + 0.37 * k, 0.5 * k));
  const ndtom::ScanContext scan{geometry, options, o, pool};
  Grouping serial;
  group(scan, points, nullptr, serial);
  const CellIndex &lo = serial.points.ends_lo, &hi = serial.points.ends_hi;
  ASSERT_GT(double(hi.x - lo.x) / ndtom::kBlockEdge * double(hi.y - lo.y) / ndtom::kBlockEdge,
            double(1 << 20));
  for (const ndtom::TileOwnership owned :
       {ndtom::TileOwnership{1, 0, 2}, ndtom::TileOwnership{2, 1, 3}}) {
    SCOPED_TRACE(testing::Message() << "tiles of " << owned.tile_blocks << " blocks, rank "
                                    << owned.rank << " of " << owned.ranks);
    expectProcessGrouping(scan, points, owned, serial);
  }
}

TEST(RayEnds, AProcessWithoutHitsInItsTilesGroupsNothing) {
  ndtom::WorkerPool pool;
  const ndtom::GridGeometry geometry(0.2);
  ndtom::ScanOptions options;
  const Eigen::Vector3d origin(0.1, 0.1, 0.1);
  const std::vector<Eigen::Vector3d> points{
      {1.01, 1.01, 0.51}, {1.21, 1.01, 0.51}, {1.41, 1.01, 0.51}};  // 3 cells, 1 block
  const ndtom::ScanContext scan{geometry, options, origin, pool};
  const CellIndex tile = ndtom::blockOf(geometry.cellOf(points[0]));  // tiles of one block
  for (int rank = 0; rank < 2; ++rank) {
    const ndtom::TileOwnership owned{1, rank, 2};
    Grouping part;
    group(scan, points, &owned, part);
    const size_t expected = owned.ownsTile(tile) ? 3 : 0;
    EXPECT_EQ(part.sorted.words.size(), expected) << "rank " << rank;
    EXPECT_EQ(part.groups.groups.size(), expected) << "rank " << rank;
  }
}
