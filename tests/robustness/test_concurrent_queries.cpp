// The threading contract: const queries may run from several threads at once on one map.
// Built with ThreadSanitizer (the core's sources compiled into this test), so a data race
// in any const path fails the test. Each thread also checks its answers against a
// single-threaded reference.
#include <gtest/gtest.h>

#include <atomic>
#include <random>
#include <thread>

#include "ndtom/files/map_io.h"
#include "ndtom/map/ndt_map.h"
#include "ndtom/matching/gaussian_lookup.h"
#include "ndtom/matching/ndt_likelihood.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

using Eigen::Vector3d;

namespace {

struct Answers {
  double occupancy_sum = 0;
  size_t gaussians = 0;
  double likelihood = 0;
  size_t bytes = 0;
};

// Every const query the map and its prepared lookup offer, over the same probe points.
Answers queryEverything(const ndtom::NdtMap& map, const ndtom::GaussianLookup& lookup,
                        const std::vector<Vector3d>& probes) {
  Answers a;
  for (const Vector3d& p : probes) {
    if (const auto occ = map.occupancyProbability(p)) a.occupancy_sum += *occ;
    if (const auto c = map.cellAt(p))
      if (const auto g = map.gaussian(c->index)) a.gaussians += g->n;
  }
  map.forEachGaussian([&](const ndtom::Gaussian& g) { a.gaussians += g.n > 0; });
  a.likelihood = ndtom::scanLikelihood(lookup, probes, ndtom::LikelihoodOptions{}).log_likelihood;
  a.bytes = ndtom::encodeMap(map).size() + map.numGaussians() + map.coarsened(2).numCells();
  return a;
}

}  // namespace

TEST(ConcurrentQueries, ConstQueriesFromManyThreadsAgreeAndDoNotRace) {
  const std::string dir = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld/";
  const auto poses = ndtom::io::readPoseFile(dir + "poses.txt");
  ndtom::MapOptions o;
  o.resolution = 0.5;
  o.scan.max_range = 30;
  ndtom::NdtMap map(o);
  std::vector<Vector3d> probes;
  for (int i = 0; i < 2; ++i) {
    auto cloud = ndtom::io::readPcd(dir + "full" + std::to_string(i) + ".pcd");
    for (auto& p : cloud.points) p = poses[i].pose * p;
    map.insertScan(cloud.points, poses[i].pose.translation());
    for (size_t k = 0; k < cloud.points.size(); k += 50) probes.push_back(cloud.points[k]);
  }
  const ndtom::GaussianLookup lookup(map);
  const Answers reference = queryEverything(map, lookup, probes);
  ASSERT_GT(reference.gaussians, 100u);

  constexpr int kThreads = 4;
  std::atomic<int> mismatches{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&] {
      for (int round = 0; round < 3; ++round) {
        const Answers a = queryEverything(map, lookup, probes);
        if (a.occupancy_sum != reference.occupancy_sum || a.gaussians != reference.gaussians ||
            a.likelihood != reference.likelihood || a.bytes != reference.bytes)
          ++mismatches;
      }
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(mismatches.load(), 0);
}
