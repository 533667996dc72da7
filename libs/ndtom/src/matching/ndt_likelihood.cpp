#include "ndtom/matching/ndt_likelihood.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace ndtom {
namespace {

// exp(−½·9): the value of a Gaussian 3σ away, the threshold for counting a point as matched.
const double kMatchedValue = std::exp(-4.5);

double valueOf(const PreparedGaussian* g, const Eigen::Vector3d& point) {
  return g ? std::exp(-0.5 * squaredMahalanobis(*g, point)) : 0.0;
}

}  // namespace

void validate(const LikelihoodOptions& options) {
  if (!(options.outlier_likelihood > 0 && options.outlier_likelihood < 1)) {
    std::ostringstream msg;
    msg << "outlier_likelihood = " << options.outlier_likelihood << ": must be in (0, 1)";
    throw std::invalid_argument(msg.str());
  }
}

double bestGaussianValue(const GaussianLookup& lookup, const Eigen::Vector3d& point,
                         bool search_neighbours) {
  if (!lookup.geometry().inRange(point)) return 0.0;
  const CellIndex home = lookup.geometry().cellOf(point);
  if (!search_neighbours) return valueOf(lookup.find(home), point);
  // The best value is the smallest Mahalanobis distance: one exp() per point.
  double best_d2 = std::numeric_limits<double>::infinity();
  lookup.forEachAround(home, [&](const PreparedGaussian& g) {
    best_d2 = std::min(best_d2, squaredMahalanobis(g, point));
  });
  return std::exp(-0.5 * best_d2);
}

ScanLikelihood scanLikelihood(const GaussianLookup& lookup,
                              const std::vector<Eigen::Vector3d>& points,
                              const LikelihoodOptions& options) {
  validate(options);
  const double c = options.outlier_likelihood;
  ScanLikelihood result;
  for (const Eigen::Vector3d& p : points) {
    if (!p.allFinite()) continue;
    const double value = bestGaussianValue(lookup, p, options.search_neighbours);
    result.log_likelihood += std::log((1.0 - c) * value + c);
    ++result.points_scored;
    result.points_matched += value >= kMatchedValue;
  }
  return result;
}

}  // namespace ndtom
