#include "ndtom_eval/map_similarity.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "ndtom/map/eigenvalue_floor.h"
#include "ndtom/map/ndt_map.h"

namespace ndtom {

namespace {

/// Cholesky factor of a positive-definite covariance; throws otherwise, naming the cell.
Eigen::LLT<Eigen::Matrix3d> factor(const Eigen::Matrix3d& m, const CellIndex& cell) {
  Eigen::LLT<Eigen::Matrix3d> llt(m);
  const bool ok = m.allFinite() && llt.info() == Eigen::Success &&
                  (llt.matrixLLT().diagonal().array() > 0.0).all();
  if (!ok)
    throw std::invalid_argument("gaussianSimilarity: covariance of cell (" +
                                std::to_string(cell.x) + ", " + std::to_string(cell.y) + ", " +
                                std::to_string(cell.z) + ") is not positive definite");
  return llt;
}

double logDeterminant(const Eigen::LLT<Eigen::Matrix3d>& llt) {
  return 2.0 * llt.matrixLLT().diagonal().array().log().sum();
}

}  // namespace

Eigen::Matrix3d flooredCovariance(const Eigen::Matrix3d& covariance, const CovarianceFloor& floor) {
  if (!(floor.min_eigenvalue > 0.0) || !std::isfinite(floor.min_eigenvalue))
    throw std::invalid_argument("CovarianceFloor.min_eigenvalue: must be finite and > 0");
  const FlooredEigen floored = floorEigenvalues(covariance, floor.min_eigenvalue);
  return floored.raised ? floored.matrix() : covariance;
}

double gaussianSimilarity(const Gaussian& f, const Gaussian& g) {
  // log s = ¼ log|2P_f| + ¼ log|2P_g| − ½ log|P_f + P_g| − ½ dᵀ(P_f + P_g)⁻¹d; the (2π)^(3/2)
  // factors cancel. For f == g, P_f + P_g is bit for bit 2P_f, so log s is exactly 0; every
  // step is symmetric in (f, g) under floating point too (d → −d flips no rounding).
  const auto llt_f = factor(2.0 * f.covariance, f.cell);
  const auto llt_g = factor(2.0 * g.covariance, g.cell);
  const auto llt_sum = factor(f.covariance + g.covariance, f.cell);
  const Eigen::Vector3d d = f.mean - g.mean;
  const double mahalanobis = d.dot(llt_sum.solve(d));
  const double log_s = 0.25 * (logDeterminant(llt_f) + logDeterminant(llt_g)) -
                       0.5 * logDeterminant(llt_sum) - 0.5 * mahalanobis;
  return std::min(1.0, std::exp(log_s));  // ≤ 1 by Cauchy-Schwarz, up to rounding
}

double mapSimilarity(const GaussianSet& test, const GaussianSet& reference) {
  if (reference.empty()) return 0.0;
  double sum = 0.0;
  for (const auto& [cell, g] : test) {
    const auto it = reference.find(cell);
    if (it != reference.end()) sum += gaussianSimilarity(g, it->second);
  }
  return sum / double(reference.size());
}

GaussianSet gaussianSetOf(const NdtMap& map, const CovarianceFloor& floor) {
  GaussianSet set;
  set.reserve(map.numGaussians());
  map.forEachGaussian(
      [&](const Gaussian& g) {
        Gaussian floored = g;
        floored.covariance = flooredCovariance(g.covariance, floor);
        set.emplace(g.cell, floored);
      },
      Covariance::Exact);
  return set;
}

GaussianSet gaussianSetOf(const CellStatsMap& stats, const GridGeometry& geometry,
                          const CovarianceFloor& floor) {
  GaussianSet set;
  set.reserve(stats.size());
  for (const auto& [cell, s] : stats) {
    if (!s.hasGaussian()) continue;
    Gaussian g;
    g.cell = cell;
    g.n = s.n;
    g.mean = geometry.cellCenter(cell) + s.relative_mean;
    g.covariance = flooredCovariance(s.covariance(), floor);
    set.emplace(cell, g);
  }
  return set;
}

double scanSimilarity(const std::vector<Eigen::Vector3d>& points, const GaussianSet& map,
                      const GridGeometry& geometry, const CovarianceFloor& floor) {
  return mapSimilarity(map, gaussianSetOf(batchNdt(points, geometry), geometry, floor));
}

}  // namespace ndtom
