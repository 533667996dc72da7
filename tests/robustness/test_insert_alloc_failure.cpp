// An insertion that fails half-way (here: an allocation fails) leaves the map exactly as it
// was. Every allocation the insertion makes is failed in turn.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>

#include "ndtom/files/map_io.h"
#include "ndtom/map/ndt_map.h"

namespace {
// Counts down allocations while armed; the one that reaches zero throws std::bad_alloc.
std::atomic<long> g_allocations_left{-1};
}  // namespace

// GCC cannot see that these replace the global pair, and warns about malloc/free.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

void* operator new(std::size_t size) {
  if (g_allocations_left.load() >= 0 && g_allocations_left.fetch_sub(1) == 0) {
    g_allocations_left = -1;
    throw std::bad_alloc();
  }
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

using Eigen::Vector3d;

namespace {

std::vector<Vector3d> scanOfARoom(std::mt19937& rng, double shift) {
  std::uniform_real_distribution<double> u(-3, 3);
  std::vector<Vector3d> pts;
  for (int i = 0; i < 3000; ++i) {
    const double a = u(rng), b = u(rng);
    pts.emplace_back(i % 2 ? Vector3d(4 + shift, a, b / 2) : Vector3d(a, b, -1.0));
  }
  return pts;
}

}  // namespace

TEST(InsertAllocationFailure, MapIsUnchangedWhateverAllocationFails) {
  for (const auto mode : {ndtom::RayMode::PerPoint, ndtom::RayMode::PerHitCell}) {
    for (const int threads : {1, 2}) {
      ndtom::MapOptions o;
      o.resolution = 0.25;
      o.scan.ray_mode = mode;
      o.scan.threads = threads;
      ndtom::NdtMap map(o);
      std::mt19937 rng(3);
      map.insertScan(scanOfARoom(rng, 0), Vector3d(0, 0, 0));
      // The next scan sees the wall moved back: cells get emptied, blocks and statistics
      // get created.
      const auto next = scanOfARoom(rng, 1.5);
      const auto before = ndtom::encodeMap(map);
      int failures = 0;
      for (long k = 0;; ++k) {
        ndtom::NdtMap attempt = map;
        g_allocations_left = k;
        try {
          attempt.insertScan(next, Vector3d(0.1, 0, 0));
          g_allocations_left = -1;
        } catch (const std::bad_alloc&) {
          ++failures;
          ASSERT_EQ(ndtom::encodeMap(attempt), before) << "allocation " << k << " failed";
          continue;
        }
        // Allocation k was never reached: the insertion succeeded, and it is complete.
        EXPECT_NE(ndtom::encodeMap(attempt), before);
        ndtom::NdtMap reference = map;
        reference.insertScan(next, Vector3d(0.1, 0, 0));
        EXPECT_EQ(ndtom::encodeMap(attempt), ndtom::encodeMap(reference));
        break;
      }
      EXPECT_GT(failures, 5);
    }
  }
}
