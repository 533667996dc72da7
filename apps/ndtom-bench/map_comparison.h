// How far a faster NDT-OM variant's map is from a reference map built from the same scans.
#pragma once

#include <optional>
#include <string>

namespace ndtom {
class NdtMap;
}

namespace ndtom::bench {

struct MapComparison {
  std::string reference;   ///< label of the reference run
  bool identical = false;  ///< encodeMap bytes equal (the multi-threaded map must be)
  size_t gaussians_reference = 0, gaussians_test = 0;
  size_t cells_reference = 0, cells_test = 0;
  /// Share of the cells known in either map that are occupied (log-odds > 0) in one and not
  /// in the other (unknown counts as not occupied).
  double occupancy_mismatch = 0;
  /// The mean-L2 map similarity of design.md (1 = identical); empty with a core that has no
  /// ndtom/map_similarity.h.
  std::optional<double> similarity;
};

MapComparison compareMaps(const std::string& reference_label, const NdtMap& reference,
                          const NdtMap& test);

}  // namespace ndtom::bench
