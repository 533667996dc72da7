#include "ndtom_eval/error_refinement.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "map/ray_dda.h"
#include "ndtom/map/insertion_report.h"
#include "ndtom/map/options.h"

namespace ndtom {

namespace {

void require(bool ok, const char* option, const char* why) {
  if (!ok) throw std::invalid_argument(std::string(option) + ": " + why);
}

double logOdds(double p) {
  return std::log(p / (1.0 - p));
}

}  // namespace

void validate(const ErrorRefinementOptions& o) {
  require(o.resolution >= kMinResolution && o.resolution <= kMaxResolution, "resolution",
          "must be within [1e-3, 1e3] m");
  require(o.e_min > 0.0 && o.e_min <= 1.0, "e_min", "must be in (0, 1]");
  require(o.e_max > 0.0 && o.e_max <= 1.0, "e_max", "must be in (0, 1]");
  require(o.o_max > 0.0 && std::isfinite(o.o_max), "o_max", "must be finite and > 0");
  require(o.p_hit > 0.5 && o.p_hit < 1.0, "p_hit", "must be in (0.5, 1)");
  require(o.p_miss > 0.0 && o.p_miss <= 0.5, "p_miss", "must be in (0, 0.5]");
  require(o.min_range >= 0.0 && std::isfinite(o.min_range), "min_range", "must be finite and >= 0");
  require(o.max_range > o.min_range, "max_range", "must be > min_range");
}

double errorRefinementRate(double occ, const ErrorRefinementOptions& o) {
  const double clamped = std::clamp(occ, -o.o_max, o.o_max);
  return ((o.e_min - o.e_max) / (2.0 * o.o_max)) * (clamped + o.o_max) + o.e_max;
}

void refineGaussian(Eigen::Vector3d& mean, Eigen::Matrix3d& covariance, const Eigen::Vector3d& x,
                    double epsilon) {
  mean += epsilon * (x - mean);
  const Eigen::Vector3d d = x - mean;
  covariance += epsilon * (d * d.transpose() - covariance);
}

ErrorRefinementMap::ErrorRefinementMap(const ErrorRefinementOptions& options)
    : options_(options), geometry_(options.resolution) {
  validate(options_);
}

ErrorRefinementReport ErrorRefinementMap::insertScan(const std::vector<Eigen::Vector3d>& points,
                                                     const Eigen::Vector3d& sensor_origin) {
  if (!geometry_.inRange(sensor_origin))
    throw std::invalid_argument("insertScan: sensor origin is not finite or outside the grid");
  ErrorRefinementReport report;
  std::vector<Eigen::Vector3d> ray_ends;
  const auto hits = hitsByCell(points, sensor_origin, ray_ends, report);
  // Free rays are counted against the Gaussians that existed before this scan.
  const auto free_rays = freeRaysThroughGaussians(ray_ends, sensor_origin);

  const double miss = logOdds(options_.p_miss);
  for (const auto& [index, count] : free_rays) {
    if (hits.count(index)) continue;  // Eq. 12: a cell hit by the scan takes the hit update
    Cell& cell = cells_.at(index);
    cell.occ = std::clamp(cell.occ + count * miss, -options_.o_max, options_.o_max);
  }
  for (const auto& [index, relative] : hits) updateHitCell(index, relative, report);
  return report;
}

// Hits grouped by cell, cell-centred, in arrival order; every used ray end in `ray_ends`.
std::unordered_map<CellIndex, std::vector<Eigen::Vector3d>, CellIndexHash>
ErrorRefinementMap::hitsByCell(const std::vector<Eigen::Vector3d>& points,
                               const Eigen::Vector3d& origin,
                               std::vector<Eigen::Vector3d>& ray_ends,
                               ErrorRefinementReport& report) const {
  std::unordered_map<CellIndex, std::vector<Eigen::Vector3d>, CellIndexHash> hits;
  const double max_ray_length = kMaxRayCells * geometry_.resolution();
  ray_ends.reserve(points.size());
  for (const Eigen::Vector3d& p : points) {
    const double range = (p - origin).norm();
    if (!geometry_.inRange(p) || range == 0.0 || range < options_.min_range ||
        std::min(range, options_.max_range) > max_ray_length) {
      ++report.points_rejected;
      continue;
    }
    if (range > options_.max_range) {
      ray_ends.push_back(origin + (p - origin) * (options_.max_range / range));
      ++report.points_rejected;
      continue;
    }
    ray_ends.push_back(p);
    const CellIndex c = geometry_.cellOf(p);
    hits[c].push_back(p - geometry_.cellCenter(c));
    ++report.points_used;
  }
  return hits;
}

// N_e of Eq. 12 for the cells holding a Gaussian: one exact traversal per ray.
std::unordered_map<CellIndex, uint32_t, CellIndexHash> ErrorRefinementMap::freeRaysThroughGaussians(
    const std::vector<Eigen::Vector3d>& ray_ends, const Eigen::Vector3d& origin) const {
  std::unordered_map<CellIndex, uint32_t, CellIndexHash> counts;
  if (num_gaussians_ == 0) return counts;
  for (const Eigen::Vector3d& end : ray_ends) {
    traverseRay(geometry_, origin, end, [&](const CellIndex& c) {
      const auto it = cells_.find(c);
      if (it != cells_.end() && it->second.has_gaussian) ++counts[c];
      return true;
    });
  }
  return counts;
}

void ErrorRefinementMap::updateHitCell(const CellIndex& index,
                                       const std::vector<Eigen::Vector3d>& relative,
                                       ErrorRefinementReport& report) {
  Cell& cell = cells_[index];
  cell.n += uint32_t(relative.size());
  if (cell.has_gaussian) {
    const double epsilon = errorRefinementRate(cell.occ, options_);  // occ before this scan
    for (const Eigen::Vector3d& x : relative)
      refineGaussian(cell.relative_mean, cell.covariance, x, epsilon);
    report.points_refined += relative.size();
  } else {
    cell.pending.merge(CellStats::fromPoints(relative));
    if (!cell.pending.hasGaussian()) return;  // no Gaussian yet, so no occupancy either
    cell.has_gaussian = true;
    cell.relative_mean = cell.pending.relative_mean;
    cell.covariance = cell.pending.covariance();
    cell.pending = CellStats{};
    cell.occ = 0.0;
    ++num_gaussians_;
    ++report.gaussians_created;
  }
  const double hit = logOdds(options_.p_hit);
  cell.occ = std::clamp(cell.occ + double(relative.size()) * hit, -options_.o_max, options_.o_max);
}

Gaussian ErrorRefinementMap::toGaussian(const CellIndex& index, const Cell& cell) const {
  Gaussian g;
  g.cell = index;
  g.n = cell.n;
  g.mean = geometry_.cellCenter(index) + cell.relative_mean;
  g.covariance = cell.covariance;
  return g;
}

std::optional<Gaussian> ErrorRefinementMap::gaussian(const CellIndex& index) const {
  const auto it = cells_.find(index);
  if (it == cells_.end() || !it->second.has_gaussian) return std::nullopt;
  return toGaussian(index, it->second);
}

std::optional<double> ErrorRefinementMap::occupancy(const CellIndex& index) const {
  const auto it = cells_.find(index);
  if (it == cells_.end() || !it->second.has_gaussian) return std::nullopt;
  return it->second.occ;
}

GaussianSet gaussianSetOf(const ErrorRefinementMap& map, const CovarianceFloor& floor) {
  GaussianSet set;
  set.reserve(map.numGaussians());
  map.forEachGaussian([&](const Gaussian& g) {
    Gaussian floored = g;
    floored.covariance = flooredCovariance(g.covariance, floor);
    set.emplace(g.cell, floored);
  });
  return set;
}

}  // namespace ndtom
