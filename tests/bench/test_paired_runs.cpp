// The benchmark's side-by-side replay (runPaired): both systems see every scan once per repeat,
// in order, from a fresh map, taking turns of kScansPerTurn scans; the insertion times come
// back per system.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "bench_runner.h"

namespace {

using ndtom::bench::MappingSystem;
using ndtom::bench::MapSize;
using ndtom::bench::Scan;
using ndtom::bench::ScanSet;

/// Records every call, with the system's name, in one shared log.
class RecordingSystem : public MappingSystem {
 public:
  RecordingSystem(std::string name, std::vector<std::pair<std::string, int>>& log,
                  std::chrono::milliseconds per_scan = {})
      : name_(std::move(name)), log_(log), per_scan_(per_scan) {}
  std::string label() const override { return name_; }
  void reset() override { log_.push_back({name_, -1}); }
  void insertScan(const Scan& scan) override {
    log_.push_back({name_, int(scan.points.size())});
    std::this_thread::sleep_for(per_scan_);
  }
  uint64_t lastScanVisits(const Scan&) override { return 0; }
  MapSize mapSize() const override { return {}; }

 private:
  std::string name_;
  std::vector<std::pair<std::string, int>>& log_;
  std::chrono::milliseconds per_scan_;
};

}  // namespace

TEST(PairedRuns, BothSystemsSeeEveryScanInOrderTakingShortAlternatingTurns) {
  constexpr int kScans = 11, kRepeats = 2;
  ScanSet set;
  set.name = "counted";
  for (int i = 0; i < kScans; ++i) {  // scan i has i + 1 points: the log tells which it was
    Scan scan;
    scan.points.assign(size_t(i + 1), Eigen::Vector3d::Zero());
    set.scans.push_back(scan);
  }
  std::vector<std::pair<std::string, int>> log;
  // b takes 3 ms a scan, a nothing: each side's time must be its own inserts'.
  RecordingSystem a("a", log), b("b", log, std::chrono::milliseconds(3));
  ndtom::apps::Progress quiet(false);
  const ndtom::bench::PairedSeconds seconds = ndtom::bench::runPaired(a, b, set, kRepeats, quiet);
  EXPECT_GE(seconds.second, kScans * kRepeats * 0.003);
  EXPECT_GE(seconds.first, 0.0);
  EXPECT_LT(seconds.first, 0.5 * seconds.second);

  // Per system: a reset, then scans 1..kScans, once per repeat.
  for (const std::string name : {"a", "b"}) {
    std::vector<int> seen;
    for (const auto& [who, what] : log)
      if (who == name) seen.push_back(what);
    std::vector<int> expected;
    for (int r = 0; r < kRepeats; ++r) {
      expected.push_back(-1);
      for (int i = 1; i <= kScans; ++i) expected.push_back(i);
    }
    EXPECT_EQ(seen, expected) << name;
  }
  // Turns: runs of one system's inserts, a's then b's over the same scans, kScansPerTurn
  // of them (fewer at the end of a repeat).
  std::vector<std::pair<std::string, std::vector<int>>> turns;
  for (const auto& [who, what] : log) {
    if (what < 0) continue;
    if (turns.empty() || turns.back().first != who) turns.push_back({who, {}});
    turns.back().second.push_back(what);
  }
  const size_t per_repeat =
      (kScans + ndtom::bench::kScansPerTurn - 1) / ndtom::bench::kScansPerTurn;
  ASSERT_EQ(turns.size(), 2 * kRepeats * per_repeat);
  for (size_t k = 0; k < turns.size(); k += 2) {
    EXPECT_EQ(turns[k].first, "a");
    EXPECT_EQ(turns[k + 1].first, "b");
    EXPECT_EQ(turns[k].second, turns[k + 1].second);
    const size_t expected_size = (k / 2) % per_repeat + 1 < per_repeat
                                     ? ndtom::bench::kScansPerTurn
                                     : kScans - (per_repeat - 1) * ndtom::bench::kScansPerTurn;
    EXPECT_EQ(turns[k].second.size(), expected_size) << "turn " << k;
  }
}

TEST(PairedRuns, ShortReplaysArePooledUntilTheFasterSideHasRunLongEnough) {
  using ndtom::bench::pairedRepeats;
  EXPECT_EQ(pairedRepeats(0.3, 3, 2.5), 9);   // ceil(2.5 / 0.3)
  EXPECT_EQ(pairedRepeats(1.0, 3, 2.5), 3);   // the minimum wins
  EXPECT_EQ(pairedRepeats(0.5, 3, 2.5), 5);   // exactly 2.5 s
  EXPECT_EQ(pairedRepeats(0.05, 1, 2.5), 50);
  EXPECT_EQ(pairedRepeats(1e-9, 3, 2.5), 100);  // capped
  EXPECT_EQ(pairedRepeats(0.0, 4, 2.5), 4);     // nothing timed: the minimum
}
