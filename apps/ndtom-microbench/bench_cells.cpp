// Cell lookup (NdtMap::cell on known and unknown cells) and the RCU merge (CellStats::merge).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <random>

#include "microbench_data.h"

namespace {

using ndtom::CellIndex;

/// A 0.2 m map of the first real scan and a shuffled list of its known cells.
struct LookupFixture {
  ndtom::NdtMap map{ndtom::microbench::benchOptions(0.2, ndtom::RayMode::PerPoint)};
  std::vector<CellIndex> known;
  LookupFixture() {
    const auto& scan = ndtom::microbench::realScans(1).front();
    map.insertScan(scan.points, scan.origin);
    map.forEachCell([&](const ndtom::CellView& c) { known.push_back(c.index); });
    std::shuffle(known.begin(), known.end(), std::mt19937(3));
  }
};

const LookupFixture& lookupFixture() {
  static const LookupFixture f;
  return f;
}

void runLookups(benchmark::State& state, const std::vector<CellIndex>& cells) {
  const ndtom::NdtMap& map = lookupFixture().map;
  size_t found = 0;
  for (auto _ : state)
    for (const CellIndex& c : cells) found += map.cell(c).has_value();
  benchmark::DoNotOptimize(found);
  state.SetItemsProcessed(int64_t(state.iterations() * cells.size()));
  state.counters["found_share"] = double(found) / double(state.iterations() * cells.size());
}

void BM_CellLookupKnown(benchmark::State& state) {
  runLookups(state, lookupFixture().known);
}

/// Unknown cells whose block does not exist: the hash lookup misses.
void BM_CellLookupUnknownBlock(benchmark::State& state) {
  std::vector<CellIndex> far = lookupFixture().known;
  for (CellIndex& c : far) c.z += 100000;
  runLookups(state, far);
}

/// Unknown cells inside known blocks: the block is found, the cell is not known.
void BM_CellLookupUnknownInKnownBlock(benchmark::State& state) {
  const LookupFixture& f = lookupFixture();
  std::vector<CellIndex> unknown;
  for (const CellIndex& c : f.known)
    for (int dz = -2; dz <= 2 && unknown.size() < f.known.size(); ++dz) {
      const CellIndex n{c.x, c.y, c.z + dz};
      if (ndtom::blockOf(n) == ndtom::blockOf(c) && !f.map.cell(n)) unknown.push_back(n);
    }
  runLookups(state, unknown);
}

BENCHMARK(BM_CellLookupKnown);
BENCHMARK(BM_CellLookupUnknownBlock);
BENCHMARK(BM_CellLookupUnknownInKnownBlock);

/// RCU merge of a batch into a cell (Eq. 2, 11), the per-hit-cell update of every scan.
void BM_CellStatsMerge(benchmark::State& state) {
  std::mt19937 rng(5);
  std::normal_distribution<double> gauss(0.0, 0.05);
  std::vector<ndtom::CellStats> batches(256);
  for (ndtom::CellStats& b : batches) {
    std::vector<Eigen::Vector3d> points(4);
    for (Eigen::Vector3d& p : points) p = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
    b = ndtom::CellStats::fromPoints(points);
  }
  ndtom::CellStats cell;
  for (auto _ : state) {
    for (const ndtom::CellStats& b : batches) cell.merge(b);
    benchmark::DoNotOptimize(cell);
  }
  state.SetItemsProcessed(int64_t(state.iterations() * batches.size()));
}
BENCHMARK(BM_CellStatsMerge);

}  // namespace
