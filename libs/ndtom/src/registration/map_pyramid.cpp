#include "ndtom/registration/map_pyramid.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <thread>

#include "registration/coarse_gaussians.h"

namespace ndtom {

MapPyramid::MapPyramid(const NdtMap& map, const std::vector<int>& factors, int threads)
    : factors_(factors), revision_(map.revision()) {
  if (factors.empty()) throw std::invalid_argument("level factors: none given");
  for (size_t i = 0; i < factors.size(); ++i) {
    if (factors[i] < 1 || factors[i] > 1024)
      throw std::invalid_argument("level factors: " + std::to_string(factors[i]) +
                                  " is not in [1, 1024]");
    if (i > 0 && factors[i] >= factors[i - 1])
      throw std::invalid_argument("level factors: must be given coarse to fine, decreasing");
  }
  // Coarse levels from the cells with statistics only: the coarse map's free cells, most of
  // its cells, are never needed here.
  const LookupOptions options{/*occupied_only=*/true, /*nearest_means=*/false};
  levels_.resize(factors.size());
  const auto build = [&](size_t l) {
    const int f = factors[l];
    levels_[l] = std::make_unique<const GaussianLookup>(
        f == 1 ? GaussianLookup(map, options)
               : GaussianLookup(GridGeometry(map.options().resolution * f),
                                registration::occupiedCoarseGaussians(map, f), options));
  };
  std::vector<std::thread> helpers;
  const size_t workers = std::min(factors.size(), size_t(std::max(threads, 1)));
  for (size_t t = 1; t < workers; ++t)
    helpers.emplace_back([&, t] {
      for (size_t l = t; l < factors.size(); l += workers) build(l);
    });
  for (size_t l = 0; l < factors.size(); l += workers) build(l);
  for (std::thread& h : helpers) h.join();
}

}  // namespace ndtom
