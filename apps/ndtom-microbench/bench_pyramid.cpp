// The registration pyramid of a map of real scans: built whole on 1 and 2 threads, and
// brought up to the map after one more scan (MapPyramid::follow), which an online mapper does
// before every scan instead of building it again. The map holds the first 5 scans, or
// $NDTOM_MICROBENCH_PYRAMID_SCANS of them (with a larger $NDTOM_MICROBENCH_DATA).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <string>

#include "microbench_data.h"
#include "ndtom/registration/map_pyramid.h"

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
  const ndtom::NdtMap map = mapOf(mapScans() + 1);
  size_t gaussians = 0;
  for (auto _ : state) {
    const ndtom::MapPyramid pyramid(map, kLevels, int(state.range(0)));
    gaussians = 0;
    for (size_t l = 0; l < pyramid.size(); ++l) gaussians += pyramid.level(l).size();
  }
  state.counters["gaussians"] = double(gaussians);
  state.SetLabel(std::to_string(mapScans() + 1) + " scans, levels 16 8 4 2 1, whole");
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
