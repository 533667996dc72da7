// NDT point-to-distribution likelihood of a scan against a map (Biber & Straßer 2003;
// Magnusson 2009): each point is scored by the best Gaussian of its own cell and, optionally,
// of the 26 cells around it, mixed with a uniform outlier floor so that one stray point
// cannot veto a pose:
//
//   L(p) = (1 − c) · max_g exp(−½ (p − μ_g)ᵀ Σ_g⁻¹ (p − μ_g)) + c,    log L(scan) = Σ_p log L(p)
//
// Σ_g is the regularised covariance. The Gaussians are not normalised (peak 1), so a thin
// cell does not outweigh a round one merely by being thin.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "ndtom/matching/gaussian_lookup.h"

namespace ndtom {

struct LikelihoodOptions {
  /// c: a point's likelihood never drops below this, in (0, 1) (Default: 0.05).
  double outlier_likelihood = 0.05;
  /// Also try the 26 cells around a point's cell: a smoother score whose basin is wider than
  /// one cell (Default: true).
  bool search_neighbours = true;
};

/// Throws std::invalid_argument naming the bad option.
void validate(const LikelihoodOptions& options);

struct ScanLikelihood {
  double log_likelihood = 0;  ///< Σ log L(p) over the scored points (≤ 0)
  size_t points_scored = 0;   ///< finite points
  size_t points_matched = 0;  ///< of those, points with a candidate Gaussian at d² < 9 (3σ)
};

/// The best exp(−½ d²) over the candidate Gaussians of `point` (0 if there are none).
double bestGaussianValue(const GaussianLookup& lookup, const Eigen::Vector3d& point,
                         bool search_neighbours);

/// Scores world-frame points; non-finite points are skipped. Throws on bad options.
ScanLikelihood scanLikelihood(const GaussianLookup& lookup,
                              const std::vector<Eigen::Vector3d>& points,
                              const LikelihoodOptions& options);

}  // namespace ndtom
