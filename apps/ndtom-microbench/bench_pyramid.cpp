// The registration pyramid of a map of real scans: built whole on 1 and 2 threads, and
// brought up to the map after one more scan (MapPyramid::follow), which an online mapper does
// before every scan instead of building it again. The map holds the first 5 scans, or
// $NDTOM_MICROBENCH_PYRAMID_SCANS of them (with a larger $NDTOM_MICROBENCH_DATA); the whole
// build takes the map file $NDTOM_MICROBENCH_PYRAMID_MAP instead if set (e.g. ndtom-map's of
// a city drive), and reports the share of its time on the worker threads (parallel_fraction,
// the one-thread run's is Amdahl's p) and what that predicts at 16 threads.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <string>

#include "amdahl.h"
#include "microbench_data.h"
#include "ndtom/files/map_io.h"
#include "ndtom/registration/map_pyramid.h"
#include "ndtom/support/stage_profile.h"
#include "support/stage_clock.h"

namespace {

using ndtom::microbench::benchOptions;
using ndtom::microbench::realScans;

const std::vector<int> kLevels{16, 8, 4, 2, 1};

/// Scans in the map; the next one is followed.
size_t mapScans() {
  const char* env = std::getenv("NDTOM_MICROBENCH_PYRAMID_SCANS");
  return env ? std::max<size_t>(1, std::strtoul(env, nullptr, 10)) : 5;
}

ndtom::NdtMap mapOf(size_t scans) {
  ndtom::NdtMap map(benchOptions(0.2, ndtom::RayMode::PerPoint));
  for (size_t i = 0; i < scans; ++i)
    map.insertScan(realScans(scans)[i].points, realScans(scans)[i].origin);
  return map;
}

void BM_PyramidBuild(benchmark::State& state) {
  const char* file = std::getenv("NDTOM_MICROBENCH_PYRAMID_MAP");
  static const ndtom::NdtMap map =
      file ? ndtom::loadMap(file, uint64_t(1) << 40) : mapOf(mapScans() + 1);
  size_t gaussians = 0;
  ndtom::StageProfile profile;
  for (auto _ : state) {
    ndtom::StageClock clock(&profile);
    clock.next("pyramid");
    const ndtom::MapPyramid pyramid(map, kLevels, int(state.range(0)));
    clock.stop();
    gaussians = 0;
    for (size_t l = 0; l < pyramid.size(); ++l) gaussians += pyramid.level(l).size();
  }
  const double p =
      ndtom::bench::parallelFraction(profile.parallelWallSeconds(), profile.wallSeconds());
  state.counters["gaussians"] = double(gaussians);
  state.counters["parallel_fraction"] = p;
  state.counters["predicted_s16"] = ndtom::bench::amdahlSpeedup(p, 16);
  state.SetLabel((file ? std::string(file) : std::to_string(mapScans() + 1) + " scans") +
                 ", levels 16 8 4 2 1, whole");
}
// Argument: threads.
BENCHMARK(BM_PyramidBuild)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PyramidFollow(benchmark::State& state) {
  const ndtom::NdtMap before = mapOf(mapScans());
  const auto& scan = realScans(mapScans() + 1)[mapScans()];
  for (auto _ : state) {
    state.PauseTiming();
    auto map = std::make_unique<ndtom::NdtMap>(before);
    auto pyramid = std::make_unique<ndtom::MapPyramid>(*map, kLevels, 1);
    map->insertScan(scan.points, scan.origin);
    state.ResumeTiming();
    if (!pyramid->follow(*map)) state.SkipWithError("follow refused the scan's changes");
    state.PauseTiming();
    pyramid.reset();
    map.reset();
    state.ResumeTiming();
  }
  state.SetLabel("one more scan's changes, levels 16 8 4 2 1");
}
BENCHMARK(BM_PyramidFollow)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
