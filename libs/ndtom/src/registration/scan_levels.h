// The scan as each pyramid level sees it: for P2D the centroids of its points in voxels of
// a fraction of the level's cell, for D2D its own NDT at the level's cell size. Built fine to
// coarse, each level from the one below (exact RCU merges for D2D when cells nest).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "ndtom/map/cell_stats.h"
#include "ndtom/map/gaussian.h"
#include "ndtom/registration/registration.h"
#include "support/parallel.h"

namespace ndtom::registration {

struct ScanGaussian {
  Eigen::Vector3d mean;        ///< sensor frame (m)
  Eigen::Matrix3d covariance;  ///< regularised (m²)
  double max_variance = 0;     ///< its largest eigenvalue (m²)
};

struct ScanLevel {
  std::vector<Eigen::Vector3d> points;  ///< P2D: sensor frame (m)
  std::vector<ScanGaussian> gaussians;  ///< D2D
  size_t size() const { return points.empty() ? gaussians.size() : points.size(); }
};

/// Groups of scan points by cell, the statistics' mean in the sensor frame.
struct ScanCell {
  CellIndex cell;
  CellStats stats;
};

/// Points (sensor frame, finite) grouped by cells of edge `cell_size`, in cell order.
std::vector<ScanCell> groupPoints(const std::vector<Eigen::Vector3d>& points, double cell_size);
std::vector<ScanCell> groupPoints(const std::vector<Eigen::Vector3d>& points, double cell_size,
                                  Threads threads);
/// Cells grouped again by the cell of edge `cell_size` holding their mean, merged exactly.
std::vector<ScanCell> regroup(const std::vector<ScanCell>& cells, double cell_size,
                              Threads threads);

/// One ScanLevel per level of `resolutions` (coarse to fine, m), as `options` say.
std::vector<ScanLevel> buildScanLevels(const std::vector<Eigen::Vector3d>& points,
                                       const std::vector<double>& resolutions,
                                       const RegistrationOptions& options,
                                       const Regularization& regularization);
/// The same on up to `threads.threads` threads (options.threads is not read): the same levels.
std::vector<ScanLevel> buildScanLevels(const std::vector<Eigen::Vector3d>& points,
                                       const std::vector<double>& resolutions,
                                       const RegistrationOptions& options,
                                       const Regularization& regularization, Threads threads);

}  // namespace ndtom::registration
