// Map similarity of the paper's evaluation (Sec. IV-A, "mean L2"; Stoyanov et al. 2012):
// per cell, the normalised L2 inner product of two Gaussians,
//   s(f, g) = <f,g> / sqrt(<f,f> <g,g>),   <f,g> = N(μ_f; μ_g, P_f + P_g),
// which is 1 for identical Gaussians and falls towards 0 as they part. A map's similarity to
// a reference is the sum of s over the cells with a Gaussian in the test map (cells without a
// Gaussian in the reference add 0), divided by the number of Gaussians in the reference.
#pragma once

#include <Eigen/Core>
#include <unordered_map>
#include <vector>

#include "ndtom/map/cell_index.h"
#include "ndtom/map/gaussian.h"
#include "ndtom_eval/batch_ndt.h"

namespace ndtom {

class NdtMap;

/// The Gaussians of a map, one per cell, covariances ready for comparison (see CovarianceFloor).
using GaussianSet = std::unordered_map<CellIndex, Gaussian, CellIndexHash>;

/// What the comparison does with singular covariances (3-point cells, exactly planar or
/// collinear points): eigenvalues below `min_eigenvalue` are raised to it. A covariance whose
/// eigenvalues are all above the floor is used exactly as estimated, bit for bit.
struct CovarianceFloor {
  double min_eigenvalue = 1e-6;  ///< (Default: 1e-6 m², i.e. σ ≥ 1 mm along every axis)
};

/// `covariance` unchanged if its smallest eigenvalue is ≥ floor.min_eigenvalue, else with
/// every eigenvalue below the floor raised to it.
Eigen::Matrix3d flooredCovariance(const Eigen::Matrix3d& covariance, const CovarianceFloor& floor);

/// s(f, g) in [0, 1]; exactly symmetric and exactly 1 for f == g. Throws std::invalid_argument
/// if a covariance is not positive definite (floor it first).
double gaussianSimilarity(const Gaussian& f, const Gaussian& g);

/// Σ_{cells with a Gaussian in test} s(test, reference) / |reference|. 1 for identical sets,
/// 0 for an empty reference. Throws std::invalid_argument like gaussianSimilarity.
double mapSimilarity(const GaussianSet& test, const GaussianSet& reference);

// --- Gaussian sets of the maps under comparison -----------------------------------------

/// Every cell of `map` with N ≥ 3, exact covariance, floored.
GaussianSet gaussianSetOf(const NdtMap& map, const CovarianceFloor& floor = {});
/// Every cell with N ≥ 3 of a batch estimate (batchNdt) on `geometry`, floored.
GaussianSet gaussianSetOf(const CellStatsMap& stats, const GridGeometry& geometry,
                          const CovarianceFloor& floor = {});

/// Per-scan variant (the paper's representation self-test): the scan's own NDT (Eq. 1 on
/// `points`) is the reference, `map` the test, so the result says which share of the scan's
/// Gaussians the map explains.
double scanSimilarity(const std::vector<Eigen::Vector3d>& points, const GaussianSet& map,
                      const GridGeometry& geometry, const CovarianceFloor& floor = {});

}  // namespace ndtom
