// The memory budget (issue #17, class 2): insertion refuses a scan that would take the map
// and its working memory over ScanOptions::memory_budget, before the blocks are allocated,
// with the numbers in the message, and leaves the map as it was. Memory then follows the
// budget, not how far apart a scan's few points are (100 points at 6 km took 2.7 GB).
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <random>

#include "ndtom/files/map_io.h"
#include "ndtom/map/ndt_map.h"
#include "support/lidar_scans.h"

using Eigen::Vector3d;

namespace {

// `n` points `range` metres from the origin, in random directions.
std::vector<Vector3d> farPoints(int n, double range, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Vector3d> pts;
  for (int i = 0; i < n; ++i) pts.push_back(range * Vector3d(g(rng), g(rng), g(rng)).normalized());
  return pts;
}

// A small room around the origin: a floor and a wall.
std::vector<Vector3d> room(unsigned seed, int n = 2000) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3, 3);
  std::vector<Vector3d> pts;
  for (int i = 0; i < n; ++i)
    pts.push_back(i % 2 ? Vector3d(4, u(rng), u(rng) / 2) : Vector3d(u(rng), u(rng), -1));
  return pts;
}

ndtom::ScanOptions unlimitedRange(uint64_t budget, int threads = 1) {
  ndtom::ScanOptions o;
  o.max_range = INFINITY;
  o.memory_budget = budget;
  o.threads = threads;
  return o;
}

// The message of the MemoryBudgetError that inserting `points` throws, or "".
std::string refusal(ndtom::NdtMap& map, const std::vector<Vector3d>& points,
                    const ndtom::ScanOptions& o) {
  const auto before = ndtom::encodeMap(map);
  try {
    map.insertScan(points, Vector3d(0.05, 0.05, 0.05), o);
  } catch (const ndtom::MemoryBudgetError& e) {
    EXPECT_GT(e.needed(), e.budget());
    EXPECT_EQ(e.budget(), o.memory_budget);
    EXPECT_EQ(ndtom::encodeMap(map), before) << "a refused scan changed the map";
    return e.what();
  }
  return "";
}

}  // namespace

TEST(MemoryBudget, FarPointsAreRefusedWhileTracing) {
  for (const int threads : {1, 2}) {
    ndtom::NdtMap map;
    map.insertScan(room(1), Vector3d(0, 0, 0));
    // 100 rays of 6 km cross ~4000 blocks each, 1.8 GB in all: refused at 64 MB.
    const std::string why = refusal(map, farPoints(100, 6000), unlimitedRange(64000000, threads));
    EXPECT_NE(why.find("insertScan: a scan whose rays cross more than"), std::string::npos) << why;
    EXPECT_NE(why.find("over the memory budget of 64.0"), std::string::npos) << why;
    // The map still takes scans, and takes them as if the refused one had not come.
    ndtom::NdtMap reference;
    reference.insertScan(room(1), Vector3d(0, 0, 0));
    for (ndtom::NdtMap* m : {&map, &reference}) m->insertScan(room(2), Vector3d(0.2, 0, 0));
    EXPECT_EQ(ndtom::encodeMap(map), ndtom::encodeMap(reference));
  }
}

TEST(MemoryBudget, DenseScanAtAFineResolutionIsRefusedBeforeTracing) {
  ndtom::MapOptions o;
  o.resolution = 0.001;  // the issue's --resolution 0.001 on a depth frame
  ndtom::NdtMap map(o);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vector3d> pts;
  for (int i = 0; i < 100000; ++i) pts.emplace_back(u(rng), u(rng), 3);
  const std::string why = refusal(map, pts, unlimitedRange(128000000));
  EXPECT_NE(why.find("insertScan: a scan whose hits lie in"), std::string::npos) << why;
  EXPECT_NE(why.find("(resolution 0.001 m)"), std::string::npos) << why;
}

TEST(MemoryBudget, ScanWithMorePointsThanTheBudgetHolds) {
  ndtom::NdtMap map;
  // Each point takes ~160 bytes of buffers while its scan is inserted: 10,000 need 1.6 MB.
  const std::string why = refusal(map, room(4, 10000), unlimitedRange(ndtom::kMinMemoryBudget));
  EXPECT_NE(why.find("insertScan: a scan of 10000 points"), std::string::npos) << why;
  EXPECT_THROW(map.insertScan(room(4), Vector3d(0, 0, 0), unlimitedRange(0)),
               std::invalid_argument);
}

// Within the budget nothing changes: the real scans give the same map with a tight budget as
// without one (the limit is checked when blocks are added, never per cell).
TEST(MemoryBudget, ScansWithinTheBudgetGiveTheSameMap) {
  ndtom::MapOptions o;
  o.resolution = 0.4;
  o.scan.max_range = 30;
  ndtom::NdtMap tight(o), loose(o);
  for (const auto& scan : ndtom::testing::lidarScansInWorld(4)) {
    ndtom::ScanOptions in = o.scan;
    in.memory_budget = 80000000;
    tight.insertScan(scan.points, scan.origin, in);
    in.memory_budget = uint64_t(1) << 40;
    loose.insertScan(scan.points, scan.origin, in);
  }
  EXPECT_EQ(ndtom::encodeMap(tight), ndtom::encodeMap(loose));
  EXPECT_GT(tight.numCells(), 10000u);
}

// The bound holds for the process: a child limited to its current address space plus 400 MB
// inserts 1000 points at 6 km (27 GB without a budget) under a 128 MB budget, and gets the
// budget's error, not std::bad_alloc.
TEST(MemoryBudget, HoldsUnderAnAddressSpaceLimit) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space";
#endif
  const pid_t pid = fork();
  if (pid == 0) {
    ndtom::NdtMap map;
    const auto points = farPoints(1000, 6000);
    struct rlimit limit;
    getrlimit(RLIMIT_AS, &limit);
    long vm_kb = 0;
    if (FILE* f = std::fopen("/proc/self/status", "r")) {
      char line[256];
      while (std::fgets(line, sizeof(line), f))
        if (std::sscanf(line, "VmSize: %ld", &vm_kb) == 1) break;
      std::fclose(f);
    }
    limit.rlim_cur = rlim_t(vm_kb) * 1024 + (400 << 20);
    setrlimit(RLIMIT_AS, &limit);
    try {
      map.insertScan(points, Vector3d(0, 0, 0), unlimitedRange(128000000, 2));
    } catch (const ndtom::MemoryBudgetError&) {
      _exit(0);
    } catch (const std::bad_alloc&) {
      _exit(2);
    }
    _exit(1);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "the child died of signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0) << "1: accepted, 2: std::bad_alloc";
}
