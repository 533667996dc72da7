#include "ndtom/registration/map_pyramid.h"

#include <stdexcept>
#include <string>

namespace ndtom {

MapPyramid::MapPyramid(const NdtMap& map, const std::vector<int>& factors)
    : factors_(factors), revision_(map.revision()) {
  if (factors.empty()) throw std::invalid_argument("level factors: none given");
  for (size_t i = 0; i < factors.size(); ++i) {
    if (factors[i] < 1 || factors[i] > 1024)
      throw std::invalid_argument("level factors: " + std::to_string(factors[i]) +
                                  " is not in [1, 1024]");
    if (i > 0 && factors[i] >= factors[i - 1])
      throw std::invalid_argument("level factors: must be given coarse to fine, decreasing");
  }
  const LookupOptions options{/*occupied_only=*/true, /*nearest_means=*/false};
  for (const int f : factors)
    levels_.push_back(std::make_unique<const GaussianLookup>(
        f == 1 ? GaussianLookup(map, options) : GaussianLookup(map.coarsened(f), options)));
}

}  // namespace ndtom
