#include "scan_levels.h"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace ndtom::registration {
namespace {

CellIndex cellOfPoint(const Eigen::Vector3d& p, double cell_size) {
  return GridGeometry::floorCell(p / cell_size);
}

// Evenly spread picks of at most `max_items` out of `items`.
template <class T>
std::vector<T> spreadSubset(const std::vector<T>& items, size_t max_items) {
  if (items.size() <= max_items) return items;
  std::vector<T> out;
  out.reserve(max_items);
  for (size_t k = 0; k < max_items; ++k) out.push_back(items[k * items.size() / max_items]);
  return out;
}

ScanGaussian scanGaussian(const CellStats& stats, const Regularization& regularization) {
  ScanGaussian g;
  g.mean = stats.mean;
  g.covariance = regularizedCovariance(stats.covariance(), regularization);
  g.max_variance = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(g.covariance,
                                                                  Eigen::EigenvaluesOnly)
                       .eigenvalues()[2];
  return g;
}

}  // namespace

std::vector<ScanCell> groupPoints(const std::vector<Eigen::Vector3d>& points, double cell_size) {
  std::vector<std::pair<CellIndex, uint32_t>> keyed;
  keyed.reserve(points.size());
  for (uint32_t i = 0; i < points.size(); ++i)
    keyed.emplace_back(cellOfPoint(points[i], cell_size), i);
  std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
    return a.first < b.first || (a.first == b.first && a.second < b.second);
  });
  std::vector<ScanCell> cells;
  std::vector<Eigen::Vector3d> members;
  for (size_t begin = 0; begin < keyed.size();) {
    size_t end = begin;
    members.clear();
    while (end < keyed.size() && keyed[end].first == keyed[begin].first)
      members.push_back(points[keyed[end++].second]);
    cells.push_back({keyed[begin].first, CellStats::fromPoints(members)});
    begin = end;
  }
  return cells;
}

std::vector<ScanCell> regroup(const std::vector<ScanCell>& cells, double cell_size) {
  std::vector<std::pair<CellIndex, uint32_t>> keyed;
  keyed.reserve(cells.size());
  for (uint32_t i = 0; i < cells.size(); ++i)
    keyed.emplace_back(cellOfPoint(cells[i].stats.mean, cell_size), i);
  std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
    return a.first < b.first || (a.first == b.first && a.second < b.second);
  });
  std::vector<ScanCell> out;
  for (const auto& [cell, i] : keyed) {
    if (out.empty() || out.back().cell != cell) out.push_back({cell, CellStats{}});
    out.back().stats.merge(cells[i].stats);
  }
  return out;
}

std::vector<ScanLevel> buildScanLevels(const std::vector<Eigen::Vector3d>& points,
                                       const std::vector<double>& resolutions,
                                       const RegistrationOptions& options,
                                       const Regularization& regularization) {
  const bool p2d = options.method == RegistrationMethod::P2D;
  const double scale = p2d ? options.voxel_ratio : 1.0;
  std::vector<ScanLevel> levels(resolutions.size());
  std::vector<ScanCell> cells;
  for (size_t k = resolutions.size(); k-- > 0;) {  // fine to coarse
    const double cell_size = scale * resolutions[k];
    cells = k + 1 == resolutions.size() ? groupPoints(points, cell_size) : regroup(cells, cell_size);
    ScanLevel& level = levels[k];
    if (p2d) {
      std::vector<Eigen::Vector3d> centroids;
      centroids.reserve(cells.size());
      for (const ScanCell& c : cells) centroids.push_back(c.stats.mean);
      level.points = spreadSubset(centroids, options.max_points);
    } else {
      for (const ScanCell& c : cells)
        if (c.stats.hasGaussian()) level.gaussians.push_back(scanGaussian(c.stats, regularization));
    }
  }
  return levels;
}

}  // namespace ndtom::registration
