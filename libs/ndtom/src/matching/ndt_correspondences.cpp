#include "ndtom/matching/ndt_correspondences.h"

#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "ndtom/matching/ndt_likelihood.h"

namespace ndtom {
namespace {

[[noreturn]] void fail(const char* option, double value, const char* why) {
  std::ostringstream msg;
  msg << option << " = " << value << ": " << why;
  throw std::invalid_argument(msg.str());
}

}  // namespace

void validate(const CorrespondenceOptions& o) {
  if (!(std::isfinite(o.max_distance) && o.max_distance > 0))
    fail("max_distance", o.max_distance, "must be finite and > 0");
  if (!(std::isfinite(o.angular_tolerance) && o.angular_tolerance >= 0))
    fail("angular_tolerance", o.angular_tolerance, "must be finite and >= 0");
  if (!o.pivot.allFinite()) fail("pivot", o.pivot.norm(), "must be finite");
  if (o.max_candidates < 1) fail("max_candidates", double(o.max_candidates), "must be >= 1");
  if (o.stride < 1) fail("stride", double(o.stride), "must be >= 1");
}

double squaredMahalanobisInPlane(const PreparedGaussian& g, const Eigen::Vector3d& point) {
  const Eigen::Matrix2d information = g.covariance.topLeftCorner<2, 2>().inverse();
  const Eigen::Vector2d d = (point - g.mean).head<2>();
  return d.dot(information * d);
}

Eigen::Vector3d projectOntoInPlane(const PreparedGaussian& g, const Eigen::Vector3d& point) {
  const Eigen::Matrix2d cov = g.covariance.topLeftCorner<2, 2>();
  const Eigen::Vector2d d = (point - g.mean).head<2>();
  // Closed-form smallest eigenvalue of a symmetric 2x2 matrix.
  const double half_trace = 0.5 * (cov(0, 0) + cov(1, 1));
  const double half_gap = std::hypot(0.5 * (cov(0, 0) - cov(1, 1)), cov(0, 1));
  const double lambda_min = half_trace - half_gap;
  Eigen::Vector3d target = point;
  target.head<2>() -= lambda_min * (cov.inverse() * d);
  return target;
}

CorrespondenceResult findCorrespondences(const GaussianLookup& lookup,
                                         const std::vector<Eigen::Vector3d>& points,
                                         const CorrespondenceOptions& options) {
  validate(options);
  CorrespondenceResult result;
  std::vector<PointKdTree::Neighbour> candidates;
  for (size_t i = options.first; i < points.size(); i += options.stride) {
    const Eigen::Vector3d& p = points[i];
    if (!p.allFinite()) continue;
    ++result.points_considered;
    const double radius =
        options.max_distance + options.angular_tolerance * (p - options.pivot).norm();
    const double max_sq = radius * radius;
    lookup.means().nearest(p, options.max_candidates, max_sq, candidates);
    const PreparedGaussian* best = nullptr;
    double best_maha = std::numeric_limits<double>::infinity();
    uint32_t best_index = 0;
    for (const auto& c : candidates) {
      const PreparedGaussian& g = lookup.meanOwner(c.index);
      const double maha =
          options.planar ? squaredMahalanobisInPlane(g, p) : squaredMahalanobis(g, p);
      if (maha < best_maha) {  // candidates come nearest first: ties keep the nearer mean
        best = &g;
        best_maha = maha;
        best_index = c.index;
      }
    }
    if (!best) continue;
    const Eigen::Vector3d target =
        options.planar ? projectOntoInPlane(*best, p) : projectOnto(*best, p);
    Correspondence pair{uint32_t(i), best_index, target, 0, best_maha};
    pair.squared_distance = (p - pair.target).squaredNorm();
    if (pair.squared_distance <= max_sq) result.pairs.push_back(pair);
  }
  return result;
}

double matchingRatio(const GaussianLookup& lookup, const std::vector<Eigen::Vector3d>& points,
                     double max_mahalanobis) {
  // exp(−½ d²) decreases with d, so "best value ≥ exp(−½ m²)" is "best distance ≤ m".
  const double threshold = std::exp(-0.5 * max_mahalanobis * max_mahalanobis);
  size_t finite = 0, matched = 0;
  for (const Eigen::Vector3d& p : points) {
    if (!p.allFinite()) continue;
    ++finite;
    const double value = bestGaussianValue(lookup, p, /*search_neighbours=*/true);
    matched += value > 0 && value >= threshold;
  }
  return finite ? double(matched) / double(finite) : 0.0;
}

}  // namespace ndtom
