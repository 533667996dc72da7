#include "ndtom/registration/map_pyramid.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <stdexcept>
#include <string>
#include <thread>

#include "ndtom/map/memory_budget.h"
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
  // its cells, are never needed here. The levels share what the map's memory budget leaves:
  // a sparse map (a Gaussian a block) has levels as large as itself.
  const LookupOptions options{/*occupied_only=*/true, /*nearest_means=*/false};
  const uint64_t budget = map.options().scan.memory_budget;
  std::atomic<uint64_t> used{map.memoryBytes()};
  levels_.resize(factors.size());
  std::vector<std::exception_ptr> failures(factors.size());
  const auto buildLevel = [&](size_t l) {
    const int f = factors[l];
    std::vector<Gaussian> coarse;
    if (f != 1) coarse = registration::occupiedCoarseGaussians(map, f);
    const size_t count = f == 1 ? map.numGaussians() : coarse.size();
    const uint64_t need = used += count * GaussianLookup::maxBytesPerGaussian();
    if (need > budget)
      throw MemoryBudgetError("the registration pyramid (level x" + std::to_string(f) + ", " +
                                  std::to_string(count) + " Gaussians, beside the map)",
                              need, budget);
    levels_[l] = std::make_unique<const GaussianLookup>(
        f == 1 ? GaussianLookup(map, options)
               : GaussianLookup(GridGeometry(map.options().resolution * f), coarse, options));
  };
  const auto build = [&](size_t l) {  // on a helper thread an exception would terminate
    try {
      buildLevel(l);
    } catch (...) {
      failures[l] = std::current_exception();
    }
  };
  std::vector<std::thread> helpers;
  const size_t workers = std::min(factors.size(), size_t(std::max(threads, 1)));
  for (size_t t = 1; t < workers; ++t)
    helpers.emplace_back([&, t] {
      for (size_t l = t; l < factors.size(); l += workers) build(l);
    });
  for (size_t l = 0; l < factors.size(); l += workers) build(l);
  for (std::thread& h : helpers) h.join();
  for (const std::exception_ptr& failure : failures)
    if (failure) std::rethrow_exception(failure);
}

}  // namespace ndtom
