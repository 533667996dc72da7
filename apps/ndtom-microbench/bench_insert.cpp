// NdtMap::insertScan of one real scan (the whole per-scan accumulation and update), into an
// empty map and into a map that already holds the previous scans, for both ray modes.
#include <benchmark/benchmark.h>

#include <memory>
#include <type_traits>

#include "microbench_data.h"

namespace {

using ndtom::microbench::benchOptions;
using ndtom::microbench::realScans;

constexpr size_t kPreviousScans = 5;  // scans 0-4 in the map, scan 5 inserted

/// Sets ScanOptions::threads where the core has it (multi-threaded insertion).
template <class T, class = void>
struct HasThreads : std::false_type {};
template <class T>
struct HasThreads<T, std::void_t<decltype(std::declval<T&>().threads = 1)>> : std::true_type {};

template <class Options>
bool setThreads(Options& o, int threads) {
  if constexpr (HasThreads<Options>::value) {
    o.threads = threads;
    return true;
  } else {
    return threads == 1;
  }
}

void BM_InsertScan(benchmark::State& state) {
  const auto mode = static_cast<ndtom::RayMode>(state.range(0));
  const bool into_empty = state.range(1) == 0;
  ndtom::MapOptions options = benchOptions(0.2, mode);
  if (!setThreads(options.scan, int(state.range(2)))) {
    state.SkipWithError("this core has no ScanOptions::threads");
    return;
  }
  const auto& scans = realScans(kPreviousScans + 1);
  ndtom::NdtMap previous(options);
  if (!into_empty)
    for (size_t i = 0; i < kPreviousScans; ++i)
      previous.insertScan(scans[i].points, scans[i].origin);
  const auto& scan = into_empty ? scans[0] : scans[kPreviousScans];

  std::unique_ptr<ndtom::NdtMap> map;
  size_t visits = 0;
  for (auto _ : state) {
    state.PauseTiming();
    map = std::make_unique<ndtom::NdtMap>(previous);  // also frees the last iteration's map
    state.ResumeTiming();
    visits += map->insertScan(scan.points, scan.origin).voxel_visits;
  }
  state.SetItemsProcessed(int64_t(state.iterations() * scan.points.size()));  // points/s
  state.counters["visits_per_s"] = benchmark::Counter(double(visits), benchmark::Counter::kIsRate);
  state.SetLabel(std::string(ndtom::toString(mode)) +
                 (into_empty ? ", empty map" : ", 5 scans in"));
}
// Arguments: ray mode (0 per point, 1 per hit cell), 0 = empty map / 1 = 5 scans in, threads.
BENCHMARK(BM_InsertScan)
    ->ArgsProduct({{0, 1}, {0, 1}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
