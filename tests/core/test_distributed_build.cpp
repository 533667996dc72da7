// A distributed build's process (tile_ownership.h) walks only its tiles' stretches of each
// ray and changes only its tiles' cells. Checked against the serial walk and the serial map:
// over all processes every cell of every ray is walked exactly once, and the processes' maps
// put together are the serial map bit for bit, for either ray mode and any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "map/ray_dda.h"
#include "ndtom/files/map_io.h"
#include "ndtom/scale/block_moves.h"
#include "ndtom/scale/distributed_insert.h"
#include "partition/owned_ray_walk.h"
#include "support/lidar_scans.h"
#include "support/map_equality.h"

using ndtom::CellIndex;
using ndtom::GridGeometry;
using ndtom::NdtMap;
using ndtom::TileOwnership;

namespace {

// Records the owned cells it visits, as OwnedRayWalk's walkers must, and counts its steps.
struct RecordingWalker {
  const TileOwnership* owned;
  std::map<CellIndex, int>* visited;
  CellIndex cell{};
  size_t steps = 0;
  size_t foreign = 0;  ///< visits of other processes' cells

  void start(const CellIndex& c) { cell = c; }
  template <int Axis>
  void move(int32_t step) {
    cell[Axis] += step;
    ++steps;
  }
  bool visit() {
    if (owned->ownsBlock(ndtom::blockOf(cell)))
      ++(*visited)[cell];
    else
      ++foreign;
    return true;
  }
};

std::map<CellIndex, int> serialWalk(const GridGeometry& g, const Eigen::Vector3d& from,
                                    const Eigen::Vector3d& to) {
  std::map<CellIndex, int> cells;
  ndtom::traverseRay(g, from, to, [&](const CellIndex& c) {
    ++cells[c];
    return true;
  });
  return cells;
}

// Every rank's owned walk, summed; the steps all ranks took. Ranks alternate between a table
// of owners over the ray's box and hashing every tile.
std::map<CellIndex, int> ownedWalks(const GridGeometry& g, const Eigen::Vector3d& from,
                                    const Eigen::Vector3d& to, int tile_blocks, int ranks,
                                    size_t& steps) {
  std::map<CellIndex, int> cells;
  const CellIndex a = g.cellOf(from), b = g.cellOf(to);
  const CellIndex lo = ndtom::cellwiseMin(a, b), hi = ndtom::cellwiseMax(a, b);
  for (int rank = 0; rank < ranks; ++rank) {
    const TileOwnership owned{tile_blocks, rank, ranks};
    RecordingWalker w{&owned, &cells};
    if (rank % 2 == 0)
      ndtom::OwnedRayWalk::walk(g, from, to, ndtom::TileOwnerTable(owned, lo, hi), w);
    else
      ndtom::OwnedRayWalk::walk(g, from, to, ndtom::TileOwnerTable(owned), w);
    steps += w.steps;
  }
  return cells;
}

}  // namespace

TEST(OwnedRayWalk, AllRanksTogetherWalkEachCellOfTheSerialWalkOnce) {
  std::mt19937 rng(7);
  for (const double resolution : {0.2, 0.25}) {  // 0.25: boundaries exact in binary
    const GridGeometry g(resolution);
    std::uniform_real_distribution<double> coordinate(-30, 30);
    std::uniform_int_distribution<int> lattice(-100, 100);
    for (int ray = 0; ray < 3000; ++ray) {
      Eigen::Vector3d from, to;
      if (ray % 3 == 0) {  // on cell and tile boundaries: through edges and corners
        from = Eigen::Vector3d(lattice(rng), lattice(rng), lattice(rng)) * resolution;
        to = Eigen::Vector3d(lattice(rng), lattice(rng), lattice(rng)) * resolution;
        if (ray % 6 == 0) to = from + (to - from).normalized().cwiseSign() * 16 * resolution * 3;
      } else {
        from = Eigen::Vector3d(coordinate(rng), coordinate(rng), coordinate(rng));
        to = Eigen::Vector3d(coordinate(rng), coordinate(rng), coordinate(rng));
      }
      if (ray % 5 == 1) to.z() = from.z();  // in a plane
      const auto serial = serialWalk(g, from, to);
      for (const int tile_blocks : {1, 2}) {
        for (const int ranks : {1, 2, 3}) {
          size_t steps = 0;
          const auto together = ownedWalks(g, from, to, tile_blocks, ranks, steps);
          ASSERT_EQ(together, serial) << "ray " << ray << " from " << from.transpose() << " to "
                                      << to.transpose() << ", tiles of " << tile_blocks
                                      << " blocks, " << ranks << " ranks";
        }
      }
    }
  }
}

TEST(OwnedRayWalk, RaysEndingWithinRoundingOfATileBoundaryToo) {
  // Where cellOf(end) and the walk's crossing times disagree by rounding, the walk may stop
  // short of the end cell or step past it: the owned walks must follow it either way.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coordinate(-20, 20);
  std::uniform_int_distribution<int> tile_index(-4, 4);
  for (const double resolution : {0.1, 0.2, 0.3}) {
    const GridGeometry g(resolution);
    for (int ray = 0; ray < 4000; ++ray) {
      const Eigen::Vector3d from(coordinate(rng), coordinate(rng), coordinate(rng));
      Eigen::Vector3d to(coordinate(rng), coordinate(rng), coordinate(rng));
      const int axis = ray % 3, tile_blocks = 1 + ray % 2;
      const double boundary = double(tile_index(rng) * tile_blocks * ndtom::kBlockEdge) * resolution;
      const int nudge = ray % 5 - 2;  // -2..2 ulps around the boundary
      to[axis] = boundary;
      for (int i = 0; i < std::abs(nudge); ++i)
        to[axis] = std::nextafter(to[axis], nudge > 0 ? 1e9 : -1e9);
      const auto serial = serialWalk(g, from, to);
      for (const int ranks : {2, 3}) {
        size_t steps = 0;
        ASSERT_EQ(ownedWalks(g, from, to, tile_blocks, ranks, steps), serial)
            << "ray " << ray << " to " << to.transpose() << ", resolution " << resolution;
      }
    }
  }
}

TEST(OwnedRayWalk, RaysThroughMoreStretchesThanItKeepsApartToo) {
  // Hundreds of one-block tiles along each ray: more stretches than the walk keeps apart
  // (OwnedRayWalk::kMaxStretches), so the last one kept is walked through to the end.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> coordinate(-150, 150);
  const GridGeometry g(0.2);
  for (int ray = 0; ray < 40; ++ray) {
    const Eigen::Vector3d from(coordinate(rng), coordinate(rng), coordinate(rng) / 10);
    const Eigen::Vector3d to(coordinate(rng), coordinate(rng), coordinate(rng) / 10);
    const auto serial = serialWalk(g, from, to);
    for (const int ranks : {2, 3}) {
      size_t steps = 0;
      ASSERT_EQ(ownedWalks(g, from, to, 1, ranks, steps), serial) << "ray " << ray;
    }
  }
}

TEST(TileOwnerTable, TheTableAnswersAsTheOwnershipForTilesInAndAroundItsBox) {
  for (const int tile_blocks : {1, 3, 4}) {  // 3: tiles not a power of two cells wide
    for (const int ranks : {1, 2, 5}) {
      for (int rank = 0; rank < ranks; ++rank) {
        const TileOwnership o{tile_blocks, rank, ranks};
        const CellIndex lo{-70, -5, -200}, hi{45, 90, -100};
        const ndtom::TileOwnerTable table(o, lo, hi), hashed(o);
        const int32_t edge = o.tileCells();
        // Every cell of the box, and cells three tiles beyond it on every side.
        for (int32_t z = lo.z - 3 * edge; z <= hi.z + 3 * edge; z += 7)
          for (int32_t y = lo.y - 3 * edge; y <= hi.y + 3 * edge; y += 5)
            for (int32_t x = lo.x - 3 * edge; x <= hi.x + 3 * edge; x += 3) {
              const CellIndex c{x, y, z};
              const CellIndex tile{ndtom::floorDiv(x, edge), ndtom::floorDiv(y, edge),
                                   ndtom::floorDiv(z, edge)};
              ASSERT_EQ(table.tileOf(c), tile);
              ASSERT_EQ(table.ownsCell(c), o.ownsTile(tile)) << x << " " << y << " " << z;
              ASSERT_EQ(hashed.ownsCell(c), o.ownsTile(tile));
              ASSERT_EQ(table.ownsCell(c), o.ownsBlock(ndtom::blockOf(c)));
            }
      }
    }
  }
}

TEST(OwnedRayWalk, RanksJumpOverOtherRanksTiles) {
  const GridGeometry g(0.2);
  const Eigen::Vector3d from(0.05, 0.07, 0.03), to(57.1, 23.3, 4.9);
  size_t serial_steps = 0;
  ndtom::traverseRay(g, from, to, [&](const CellIndex&) { return ++serial_steps, true; });
  for (const int ranks : {2, 4, 8}) {
    size_t steps = 0;
    ownedWalks(g, from, to, 4, ranks, steps);
    // Each rank walks about its share plus a few cells per stretch; all of them together
    // not much more than the serial walk.
    EXPECT_LT(steps, serial_steps * 5 / 4) << ranks << " ranks";
    EXPECT_GT(steps, serial_steps / 2) << ranks << " ranks";
  }
}

TEST(OwnedRayWalk, StretchesEnteredAndLeftAlongOneAxisVisitOnlyTheirOwnCells) {
  // Along x, off every other boundary: each stretch is entered and left by a step of x
  // alone, so it starts at its first cell and stops at its last. Tiles of 16 cells, and the
  // ray starts at a tile's first cell: every gap is a whole tile, longer than the walk ever
  // joins. All ranks together then visit exactly the serial walk's cells, none twice.
  const GridGeometry g(0.2);
  const Eigen::Vector3d from(0.05, 0.07, 0.03), to(80.05, 0.07, 0.03);
  const auto serial = serialWalk(g, from, to);
  for (const int ranks : {2, 3}) {
    std::map<CellIndex, int> cells;
    size_t foreign = 0, visits = 0;
    for (int rank = 0; rank < ranks; ++rank) {
      const TileOwnership owned{2, rank, ranks};
      RecordingWalker w{&owned, &cells};
      ndtom::OwnedRayWalk::walk(g, from, to, ndtom::TileOwnerTable(owned), w);
      foreign += w.foreign;
    }
    for (const auto& [cell, n] : cells) visits += size_t(n);
    EXPECT_EQ(cells, serial) << ranks << " ranks";
    EXPECT_EQ(foreign, 0u) << ranks << " ranks";
    EXPECT_EQ(visits, serial.size()) << ranks << " ranks";
  }
}

TEST(DistributedBuild, ProcessesMapsTogetherAreTheSerialMapBitForBit) {
  const auto scans = ndtom::testing::lidarScansInWorld(4);
  for (const auto mode : {ndtom::RayMode::PerPoint, ndtom::RayMode::PerHitCell}) {
    ndtom::MapOptions o;
    o.resolution = 0.4;
    o.scan.max_range = 30;
    o.scan.ray_mode = mode;
    o.occupancy.logodds_max = 1.0;  // clamps after a few scans: a merge of maps would not
    NdtMap serial(o);
    for (const auto& s : scans) serial.insertScan(s.points, s.origin);
    for (const int ranks : {1, 2, 3}) {
      for (const int threads : {1, 2}) {
        SCOPED_TRACE(testing::Message() << "mode " << int(mode) << ", " << ranks << " ranks, "
                                        << threads << " threads");
        ndtom::ScanOptions insert = o.scan;
        insert.threads = threads;
        NdtMap together(o);
        for (int rank = 0; rank < ranks; ++rank) {
          const TileOwnership owned{2, rank, ranks};
          NdtMap part(o);
          for (const auto& s : scans)
            ndtom::insertScanPart(part, s.points, s.origin, insert, owned);
          size_t foreign = 0;
          part.forEachBlock([&](const CellIndex& b) { foreign += !owned.ownsBlock(b); });
          EXPECT_EQ(foreign, 0u);
          if (ranks > 1) {
            EXPECT_LT(part.numCells(), serial.numCells() * 3 / 4);
          }
          ndtom::absorbBlocks(together, std::move(part));
        }
        ndtom::testing::expectBitIdentical(serial, together);
        EXPECT_EQ(ndtom::encodeMap(serial), ndtom::encodeMap(together));
      }
    }
  }
}

TEST(DistributedBuild, RefusesAnInvalidOwnership) {
  NdtMap map;
  const std::vector<Eigen::Vector3d> points{{1, 0, 0}};
  for (const TileOwnership bad : {TileOwnership{0, 0, 1}, TileOwnership{1, 2, 2},
                                  TileOwnership{1, -1, 2}, TileOwnership{1, 0, 0}})
    EXPECT_THROW(ndtom::insertScanPart(map, points, {0, 0, 0}, {}, bad), std::invalid_argument);
  EXPECT_TRUE(map.isEmpty());
}
