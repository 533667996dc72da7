// A distributed build whose processes share the rays out and trade counts (count_exchange.h),
// the processes run as threads here. Checked against the serial map, bit for bit, and the
// serial walk: each ray is walked by one process, so the processes' visits add up to the
// serial visits exactly; a process that fails a scan makes every process fail it, none
// changing its map.
#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>
#include <thread>

#include "ndtom/files/map_io.h"
#include "ndtom/scale/block_moves.h"
#include "ndtom/scale/distributed_insert.h"
#include "ndtom_internal/thread_count_exchange.h"
#include "support/lidar_scans.h"
#include "support/map_equality.h"

using ndtom::NdtMap;
using ndtom::TileOwnership;

namespace {

// Runs rank(r) on a thread per rank; a rank's failure is reported after all joined.
void onThreads(int ranks, const std::function<void(int)>& rank) {
  std::vector<std::thread> threads;
  std::vector<std::string> errors(static_cast<size_t>(ranks));
  for (int r = 0; r < ranks; ++r)
    threads.emplace_back([&, r] {
      try {
        rank(r);
      } catch (const std::exception& e) {
        errors[size_t(r)] = e.what();
      }
    });
  for (std::thread& t : threads) t.join();
  for (int r = 0; r < ranks; ++r) EXPECT_EQ(errors[size_t(r)], "") << "rank " << r;
}

ndtom::MapOptions clampingOptions(ndtom::RayMode mode) {
  ndtom::MapOptions o;
  o.resolution = 0.4;
  o.scan.max_range = 30;
  o.scan.ray_mode = mode;
  o.occupancy.logodds_max = 1.0;  // clamps after a few scans: a merge of maps would not
  return o;
}

}  // namespace

TEST(SharedRays, ProcessesMapsTogetherAreTheSerialMapBitForBit) {
  const auto scans = ndtom::testing::lidarScansInWorld(4);
  for (const auto mode : {ndtom::RayMode::PerPoint, ndtom::RayMode::PerHitCell}) {
    const ndtom::MapOptions o = clampingOptions(mode);
    NdtMap serial(o);
    size_t serial_visits = 0;
    for (const auto& s : scans) serial_visits += serial.insertScan(s.points, s.origin).voxel_visits;
    for (const int ranks : {1, 2, 3, 4}) {
      for (const int threads : {1, 2}) {
        SCOPED_TRACE(testing::Message() << "mode " << int(mode) << ", " << ranks << " ranks, "
                                        << threads << " threads");
        ndtom::ScanOptions insert = o.scan;
        insert.threads = threads;
        ndtom::ThreadCountExchange hub(ranks);
        std::vector<NdtMap> parts(static_cast<size_t>(ranks), NdtMap(o));
        std::vector<size_t> visits(static_cast<size_t>(ranks), 0);
        onThreads(ranks, [&](int rank) {
          const TileOwnership owned{2, rank, ranks};
          for (const auto& s : scans)
            visits[size_t(rank)] +=

                ndtom::insertScanPart(parts[size_t(rank)], s.points, s.origin, insert, owned,
                                      hub.port(rank))
                    .voxel_visits;
        });
        size_t all_visits = 0;
        NdtMap together(o);
        for (int rank = 0; rank < ranks; ++rank) {
          const TileOwnership owned{2, rank, ranks};
          size_t foreign = 0;
          parts[size_t(rank)].forEachBlock(
              [&](const ndtom::CellIndex& b) { foreign += !owned.ownsBlock(b); });
          EXPECT_EQ(foreign, 0u);
          if (ranks > 1) {
            EXPECT_LT(visits[size_t(rank)], serial_visits * 3 / 4);
          }
          all_visits += visits[size_t(rank)];
          ndtom::absorbBlocks(together, std::move(parts[size_t(rank)]));
        }
        EXPECT_EQ(all_visits, serial_visits);
        ndtom::testing::expectBitIdentical(serial, together);
        EXPECT_EQ(ndtom::encodeMap(serial), ndtom::encodeMap(together));
      }
    }
  }
}

TEST(SharedRays, AScanOneProcessFailsLeavesEveryProcessMapAsItWas) {
  const auto scans = ndtom::testing::lidarScansInWorld(3);
  const ndtom::MapOptions o = clampingOptions(ndtom::RayMode::PerHitCell);
  NdtMap serial(o);  // without the scan that fails
  serial.insertScan(scans[0].points, scans[0].origin);
  serial.insertScan(scans[2].points, scans[2].origin);
  constexpr int kRanks = 2;
  ndtom::ThreadCountExchange hub(kRanks);
  std::vector<NdtMap> parts(kRanks, NdtMap(o));
  std::vector<std::string> failures(kRanks);
  onThreads(kRanks, [&](int rank) {
    const TileOwnership owned{2, rank, kRanks};
    NdtMap& part = parts[size_t(rank)];
    ndtom::insertScanPart(part, scans[0].points, scans[0].origin, o.scan, owned, hub.port(rank));
    const std::vector<uint8_t> before = ndtom::encodeMap(part);
    ndtom::ScanOptions starved = o.scan;
    if (rank == 1) starved.memory_budget = uint64_t(1) << 20;  // the least: no room for a scan
    try {
      ndtom::insertScanPart(part, scans[1].points, scans[1].origin, starved, owned, hub.port(rank));
    } catch (const std::exception& e) {
      failures[size_t(rank)] = e.what();
    }
    EXPECT_EQ(ndtom::encodeMap(part), before) << "rank " << rank;
    ndtom::insertScanPart(part, scans[2].points, scans[2].origin, o.scan, owned, hub.port(rank));
  });
  EXPECT_NE(failures[1].find("budget"), std::string::npos) << failures[1];
  EXPECT_NE(failures[0].find("another process"), std::string::npos) << failures[0];
  NdtMap together(o);
  for (NdtMap& part : parts) ndtom::absorbBlocks(together, std::move(part));
  EXPECT_EQ(ndtom::encodeMap(serial), ndtom::encodeMap(together));
}

namespace {

// Hands back one message of its own making instead of the others'.
struct ForgingExchange : ndtom::CountExchange {
  std::vector<uint32_t> forged;
  bool exchange(bool, const std::vector<std::vector<uint32_t>>& outgoing,
                std::vector<std::vector<uint32_t>>& incoming) override {
    incoming.assign(outgoing.size(), {});
    incoming[1] = forged;
    return true;
  }
};

}  // namespace

TEST(SharedRays, RefusesAMalformedMessageAndKeepsItsMap) {
  const auto scans = ndtom::testing::lidarScansInWorld(2);
  const ndtom::MapOptions o = clampingOptions(ndtom::RayMode::PerHitCell);
  const TileOwnership owned{2, 0, 2};
  uint32_t mine = 0, theirs = 0;  // x of a block on the x axis this process owns, and not
  while (!owned.ownsBlock({int32_t(mine), 0, 0})) ++mine;
  while (owned.ownsBlock({int32_t(theirs), 0, 0})) ++theirs;
  for (const std::vector<uint32_t>& forged : std::vector<std::vector<uint32_t>>{
           {mine, 0},                   // shorter than a block's header
           {mine, 0, 0, 600},           // more cells than a block has
           {mine, 0, 0, 2, 5, 1},       // fewer pairs than it says
           {mine, 0, 0, 1, 512, 1},     // an offset outside the block
           {theirs, 0, 0, 1, 5, 1}}) {  // a block of another process's tile
    NdtMap part(o);
    ForgingExchange honest;
    ndtom::insertScanPart(part, scans[0].points, scans[0].origin, o.scan, owned, honest);
    const std::vector<uint8_t> before = ndtom::encodeMap(part);
    ForgingExchange forging;
    forging.forged = forged;
    EXPECT_THROW(
        ndtom::insertScanPart(part, scans[1].points, scans[1].origin, o.scan, owned, forging),
        std::runtime_error);
    EXPECT_EQ(ndtom::encodeMap(part), before);
    // The same scan with a well-formed message of the same block is taken.
    forging.forged = {mine, 0, 0, 1, 5, 1};
    EXPECT_NO_THROW(
        ndtom::insertScanPart(part, scans[1].points, scans[1].origin, o.scan, owned, forging));
    EXPECT_NE(ndtom::encodeMap(part), before);
  }
}
