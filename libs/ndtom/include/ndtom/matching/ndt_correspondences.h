// Point-to-Gaussian correspondences for registering a scan against the map with a point-to-
// point solver (Horn/Umeyama, as MRPT's ICP uses).
//
// For each scan point p: among the `max_candidates` Gaussian means nearest to p within
// `max_distance`, take the one with the smallest Mahalanobis distance, and pair p with its
// projection  t = p − λ_min·Σ⁻¹·(p − μ)  (see PreparedGaussian::projection): the foot of p
// on a planar cell's plane, on a linear cell's line, or a round cell's mean. Iterating
// "pair, solve, re-pair" then minimises point-to-plane distances on planar scenes while the
// solver stays point-to-point.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "ndtom/matching/gaussian_lookup.h"

namespace ndtom {

struct CorrespondenceOptions {
  /// Search radius around a point for Gaussian means, and the largest accepted |p − t|
  /// (Default: 0.5 m). Both grow by angular_tolerance·|p − pivot|.
  double max_distance = 0.5;
  /// Extra radius per metre from `pivot`, for rotation errors seen from a sensor (Default:
  /// 0 rad, a fixed radius).
  double angular_tolerance = 0.0;
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();  ///< (m)
  /// Nearest means examined per point (Default: 8).
  size_t max_candidates = 8;
  /// Use points first, first + stride, ... (Default: 0, 1: all points).
  size_t first = 0;
  size_t stride = 1;
  /// In the x-y plane, for 2D ICP: the Gaussians' x-y marginals choose and project (the
  /// foot of p on a wall's line), and the target keeps p's z. In 3D, the flat Gaussians of a
  /// map of 2D scans have their thinnest axis in z, so projecting moved points only a few
  /// percent of the way to a wall (Default: false).
  bool planar = false;
};

/// Throws std::invalid_argument naming the bad option.
void validate(const CorrespondenceOptions& options);

struct Correspondence {
  uint32_t point = 0;                                ///< index into the scan
  uint32_t gaussian = 0;                             ///< GaussianLookup::meanOwner() of it
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  ///< t, world frame (m)
  double squared_distance = 0;                       ///< |p − t|² (m²)
  double squared_mahalanobis = 0;                    ///< (p − μ)ᵀ Σ⁻¹ (p − μ)
};

struct CorrespondenceResult {
  std::vector<Correspondence> pairs;  ///< in ascending point order
  size_t points_considered = 0;       ///< finite points visited (after first/stride)
};

/// The paired point of `point` and `g`: t = p − projection·(p − μ).
inline Eigen::Vector3d projectOnto(const PreparedGaussian& g, const Eigen::Vector3d& point) {
  return point - g.projection * (point - g.mean);
}

/// (p − μ)_xyᵀ Σxy⁻¹ (p − μ)_xy, with Σxy the x-y marginal of g's covariance.
double squaredMahalanobisInPlane(const PreparedGaussian& g, const Eigen::Vector3d& point);

/// The paired point in the x-y plane: t_xy = p_xy − λmin(Σxy)·Σxy⁻¹·(p − μ)_xy, t_z = p_z.
Eigen::Vector3d projectOntoInPlane(const PreparedGaussian& g, const Eigen::Vector3d& point);

/// Correspondences of world-frame points. Throws on bad options.
CorrespondenceResult findCorrespondences(const GaussianLookup& lookup,
                                         const std::vector<Eigen::Vector3d>& points,
                                         const CorrespondenceOptions& options);

/// Fraction in [0, 1] of the finite points whose best candidate Gaussian (own cell and the
/// 26 around it) is within Mahalanobis distance `max_mahalanobis`; 0 for no finite point.
double matchingRatio(const GaussianLookup& lookup, const std::vector<Eigen::Vector3d>& points,
                     double max_mahalanobis);

}  // namespace ndtom
