// A distributed build whose processes share the rays out and trade counts (count_exchange.h),
// the processes run as threads here. Checked against the serial map, bit for bit, and the
// serial walk: each ray is walked by one process, so the processes' visits add up to the
// serial visits exactly; a process that fails a scan makes every process fail it, none
// changing its map.
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <limits>
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

namespace {

// Passes messages through `inner`; on the scan it is told, the first message this process
// receives from process 1 arrives empty (malformed).
struct TruncatingPort : ndtom::CountExchange {
  ndtom::CountExchange& inner;
  bool truncate_next = false;
  explicit TruncatingPort(ndtom::CountExchange& port) : inner(port) {}
  bool exchange(bool failed, const std::vector<std::vector<uint32_t>>& outgoing,
                std::vector<std::vector<uint32_t>>& incoming) override {
    const bool ok = inner.exchange(failed, outgoing, incoming);
    if (ok && truncate_next) incoming[1].clear();
    truncate_next = false;
    return ok;
  }
};

}  // namespace

// A process fails the scan before the exchanges (over its memory budget) or between them
// (with the points shared out, a malformed message read after the first): every process fails
// it, none changes its map, and the next scan goes on.
TEST(SharedRays, AScanOneProcessFailsLeavesEveryProcessMapAsItWas) {
  const auto scans = ndtom::testing::lidarScansInWorld(3);
  for (const auto mode : {ndtom::RayMode::PerPoint, ndtom::RayMode::PerHitCell}) {
    for (const bool over_budget : {true, false}) {
      if (!over_budget && mode == ndtom::RayMode::PerHitCell) continue;  // one exchange there
      SCOPED_TRACE(testing::Message() << "mode " << int(mode) << ", over budget " << over_budget);
      const ndtom::MapOptions o = clampingOptions(mode);
      NdtMap serial(o);  // without the scan that fails
      serial.insertScan(scans[0].points, scans[0].origin);
      serial.insertScan(scans[2].points, scans[2].origin);
      constexpr int kRanks = 2;
      ndtom::ThreadCountExchange hub(kRanks);
      std::vector<NdtMap> parts(kRanks, NdtMap(o));
      std::vector<std::string> failures(kRanks);
      const int failing = over_budget ? 1 : 0;
      onThreads(kRanks, [&](int rank) {
        const TileOwnership owned{2, rank, kRanks};
        NdtMap& part = parts[size_t(rank)];
        TruncatingPort port(hub.port(rank));
        ndtom::insertScanPart(part, scans[0].points, scans[0].origin, o.scan, owned, port);
        const std::vector<uint8_t> before = ndtom::encodeMap(part);
        ndtom::ScanOptions insert = o.scan;
        if (rank == failing && over_budget)
          insert.memory_budget = uint64_t(1) << 20;  // the least: no room for a scan
        port.truncate_next = rank == failing && !over_budget;
        try {
          ndtom::insertScanPart(part, scans[1].points, scans[1].origin, insert, owned, port);
        } catch (const std::exception& e) {
          failures[size_t(rank)] = e.what();
        }
        EXPECT_EQ(ndtom::encodeMap(part), before) << "rank " << rank;
        ndtom::insertScanPart(part, scans[2].points, scans[2].origin, o.scan, owned, port);
      });
      EXPECT_NE(failures[size_t(failing)].find(over_budget ? "budget" : "malformed"),
                std::string::npos)
          << failures[size_t(failing)];
      EXPECT_NE(failures[size_t(1 - failing)].find("another process"), std::string::npos)
          << failures[size_t(1 - failing)];
      NdtMap together(o);
      for (NdtMap& part : parts) ndtom::absorbBlocks(together, std::move(part));
      EXPECT_EQ(ndtom::encodeMap(serial), ndtom::encodeMap(together));
    }
  }
}

namespace {

// Hands back one message of its own making instead of the others' (process 1's).
struct ForgingExchange : ndtom::CountExchange {
  std::vector<uint32_t> forged;
  bool exchange(bool failed, const std::vector<std::vector<uint32_t>>& outgoing,
                std::vector<std::vector<uint32_t>>& incoming) override {
    incoming.assign(2, {});
    if (failed) return false;
    EXPECT_EQ(outgoing.size(), 2u);
    incoming[1] = forged;
    return true;
  }
};

using Words = std::vector<uint32_t>;

Words operator+(Words a, const Words& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// A message's head: point counts (hits, truncated, non-finite, too close, out of the grid,
// too far) and hits.
Words head(const ndtom::InsertionReport& r, const std::vector<Eigen::Vector3d>& hits = {}) {
  Words w{uint32_t(r.hits),
          uint32_t(r.truncated),
          uint32_t(r.rejected_non_finite),
          uint32_t(r.rejected_too_close),
          uint32_t(r.rejected_out_of_grid),
          uint32_t(r.rejected_too_far),
          uint32_t(hits.size())};
  for (const Eigen::Vector3d& p : hits) {
    uint32_t words[6];
    std::memcpy(words, p.data(), sizeof(words));
    w.insert(w.end(), words, words + 6);
  }
  return w;
}

// Inserts a scan, then the same scan again with each forged message as process 1's: each
// must be refused with the map unchanged, and then the same scan taken with `good`.
void expectRefused(ndtom::RayMode mode, const std::vector<Words>& forgeries, const Words& good) {
  const auto scans = ndtom::testing::lidarScansInWorld(2);
  const ndtom::MapOptions o = clampingOptions(mode);
  const TileOwnership owned{2, 0, 2};
  for (const Words& forged : forgeries) {
    SCOPED_TRACE(testing::Message() << "message of " << forged.size() << " words");
    NdtMap part(o);
    ForgingExchange exchange;
    exchange.forged = good;
    ndtom::insertScanPart(part, scans[1].points, scans[1].origin, o.scan, owned, exchange);
    const std::vector<uint8_t> before = ndtom::encodeMap(part);
    exchange.forged = forged;
    EXPECT_THROW(
        ndtom::insertScanPart(part, scans[1].points, scans[1].origin, o.scan, owned, exchange),
        std::runtime_error);
    EXPECT_EQ(ndtom::encodeMap(part), before);
    exchange.forged = good;
    EXPECT_NO_THROW(
        ndtom::insertScanPart(part, scans[1].points, scans[1].origin, o.scan, owned, exchange));
    EXPECT_NE(ndtom::encodeMap(part), before);
  }
}

// The message process 1 of 2 sends process 0 in its first exchange of `scan`.
Words firstMessageOfProcessOne(const ndtom::MapOptions& o, const ndtom::testing::WorldScan& scan) {
  struct RecordingPort : ndtom::CountExchange {
    ndtom::CountExchange& inner;
    Words* record;
    RecordingPort(ndtom::CountExchange& port, Words* to) : inner(port), record(to) {}
    bool exchange(bool failed, const std::vector<std::vector<uint32_t>>& outgoing,
                  std::vector<std::vector<uint32_t>>& incoming) override {
      if (record && !failed) *record = outgoing[0];
      record = nullptr;
      return inner.exchange(failed, outgoing, incoming);
    }
  };
  ndtom::ThreadCountExchange hub(2);
  Words sent;
  onThreads(2, [&](int rank) {
    NdtMap part(o);
    RecordingPort port(hub.port(rank), rank == 1 ? &sent : nullptr);
    ndtom::insertScanPart(part, scan.points, scan.origin, o.scan, TileOwnership{2, rank, 2}, port);
  });
  return sent;
}

}  // namespace

TEST(SharedRays, RefusesAMalformedMessageAndKeepsItsMap) {
  const TileOwnership owned{2, 0, 2};
  uint32_t mine = 0, theirs = 0;  // x of a block on the x axis this process owns, and not
  while (!owned.ownsBlock({int32_t(mine), 0, 0})) ++mine;
  while (owned.ownsBlock({int32_t(theirs), 0, 0})) ++theirs;
  // Per-hit-cell rays: every process classifies every point, so a head holds nothing.
  const Words nothing = head({});
  ndtom::InsertionReport one_hit;
  one_hit.hits = 1;
  const double r = clampingOptions(ndtom::RayMode::PerHitCell).resolution;
  const Eigen::Vector3d in_mine((mine * 8 + 0.5) * r, 0.5 * r, 0.5 * r);
  expectRefused(ndtom::RayMode::PerHitCell,
                {{},                                       // no head
                 head(one_hit),                            // points the process classified too
                 head({}, {in_mine}),                      // a hit it classified too
                 nothing + Words{mine, 0},                 // shorter than a block's header
                 nothing + Words{mine, 0, 0, 600},         // more cells than a block has
                 nothing + Words{mine, 0, 0, 2, 5, 1},     // fewer pairs than it says
                 nothing + Words{mine, 0, 0, 1, 512, 1},   // an offset outside the block
                 nothing + Words{theirs, 0, 0, 1, 5, 1}},  // a block of another process's tile
                nothing + Words{mine, 0, 0, 1, 5, 1});
}

// Per-point rays: process 1 classified a share of the points; its counts are taken here
// from the message it sends in a build by two processes.
TEST(SharedRays, RefusesAMalformedMessageOfHitsAndKeepsItsMap) {
  const auto scans = ndtom::testing::lidarScansInWorld(2);
  const ndtom::MapOptions o = clampingOptions(ndtom::RayMode::PerPoint);
  const Words sent = firstMessageOfProcessOne(o, scans[1]);
  ASSERT_GE(sent.size(), 7u);
  ndtom::InsertionReport half;
  half.hits = sent[0];
  half.truncated = sent[1];
  half.rejected_non_finite = sent[2];
  half.rejected_too_close = sent[3];
  half.rejected_out_of_grid = sent[4];
  half.rejected_too_far = sent[5];
  ASSERT_GT(half.hits, 0u);
  ASSERT_GT(half.truncated + half.rejected(), 0u);  // the other counts are checked too
  const TileOwnership owned{2, 0, 2};
  const double r = o.resolution;
  Eigen::Vector3d mine(0.5 * r, 0.5 * r, 0.5 * r), theirs = mine;  // hits in either's tile
  while (!owned.ownsBlock(ndtom::blockOf(ndtom::GridGeometry(r).cellOf(mine)))) mine.x() += 8 * r;
  while (owned.ownsBlock(ndtom::blockOf(ndtom::GridGeometry(r).cellOf(theirs)))) theirs.x() += 8 * r;
  ndtom::InsertionReport short_of_one = half;
  --short_of_one.hits;
  ndtom::InsertionReport one_more = half;
  ++one_more.rejected_too_far;
  Words claims_two = head(half, {mine});
  claims_two[6] = 2;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expectRefused(ndtom::RayMode::PerPoint,
                {{},                                                   // no head
                 head(short_of_one),                                   // points unaccounted for
                 head(one_more),                                       // more points than the scan
                 claims_two,                                           // fewer hits than it says
                 head(half, {theirs}),                                 // a hit of another's tile
                 head(half, {mine, theirs}),                           // ... after one of its own
                 head(half, {Eigen::Vector3d(nan, 0, 0)}),             // not a point
                 head(half, {Eigen::Vector3d(1e12, 0, 0)}),            // outside the grid
                 head(half) + Words{0, 0, 0, 600}},                    // then bad counts
                head(half, {mine}));
}
