#include "map_comparison.h"

#include "ndtom/files/map_io.h"
#include "ndtom/map/map_queries.h"
#include "ndtom/map/ndt_map.h"

// The map similarity arrived after this harness (in the core, then in ndtom_eval): use it when
// it is there, so the harness also builds (and measures) the cores from before it.
#if __has_include("ndtom_eval/map_similarity.h")
#include "ndtom_eval/map_similarity.h"
#define NDTOM_BENCH_HAS_SIMILARITY 1
#elif __has_include("ndtom/map_similarity.h")
#include "ndtom/map_similarity.h"
#define NDTOM_BENCH_HAS_SIMILARITY 1
#endif

namespace ndtom::bench {

namespace {

bool occupied(const NdtMap& map, const std::optional<CellView>& c) {
  return c && cellState(map, *c) == CellState::Occupied;
}

/// Mean-L2 similarity of `test` to `reference` (design.md), or empty with a core that has
/// no map_similarity.h: the targets then fall back to the Gaussian counts and the occupancy
/// mismatch.
std::optional<double> similarityOf(const NdtMap& reference, const NdtMap& test) {
#ifdef NDTOM_BENCH_HAS_SIMILARITY
  return mapSimilarity(gaussianSetOf(test), gaussianSetOf(reference));
#else
  (void)reference;
  (void)test;
  return std::nullopt;
#endif
}

}  // namespace

MapComparison compareMaps(const std::string& reference_label, const NdtMap& reference,
                          const NdtMap& test) {
  MapComparison c;
  c.reference = reference_label;
  c.identical = encodeMap(reference) == encodeMap(test);
  c.gaussians_reference = reference.numGaussians();
  c.gaussians_test = test.numGaussians();
  c.cells_reference = reference.numCells();
  c.cells_test = test.numCells();

  size_t union_cells = 0, mismatched = 0;
  reference.forEachCell([&](const CellView& r) {
    ++union_cells;
    mismatched += occupied(reference, r) != occupied(test, test.cell(r.index));
  });
  test.forEachCell([&](const CellView& t) {
    if (reference.cell(t.index)) return;  // counted above
    ++union_cells;
    mismatched += occupied(test, t);
  });
  c.occupancy_mismatch = union_cells > 0 ? double(mismatched) / double(union_cells) : 0;
  c.similarity = similarityOf(reference, test);
  return c;
}

}  // namespace ndtom::bench
