// Error Refinement (ER), the baseline the paper compares NDT-OM against (Sec. IV-A; Yguel,
// Aycard, Laugier 2007): each cell's Gaussian is refined point by point with a learning rate
// that depends on the cell's occupancy,
//   ε = ((e_min − e_max) / (2·o_max))·(occ + o_max) + e_max,   occ clamped to ±o_max,
//   μ ← μ + ε(x − μ);   P ← P + ε((x − μ)(x − μ)ᵀ − P)   (P uses the μ just updated).
// A confident cell (occ = o_max) learns at e_min, a doubtful one (occ = −o_max) at e_max.
//
// Choices the paper leaves open, made here as simply as faithfully possible:
//  - A cell's first Gaussian is the exact batch estimate (Eq. 1) of its first points, taken
//    at the end of the first scan after which the cell holds ≥ 3 points (the same 3-point
//    rule as the NDT maps). Every later point goes through the ER update above.
//  - occ exists only for cells holding a Gaussian (as in Yguel et al.). It starts at 0 when
//    the Gaussian is created and follows NDT-OM's Eq. 12 from that scan on: + N_p·log(p_o/
//    (1−p_o)) if the scan hits the cell, else + N_e·log(p_e/(1−p_e)) for N_e rays crossing it
//    (one ray per point, exact traversal); then clamped to ±o_max. All points of a scan in a
//    cell use the ε of the cell's occ before that scan. ER never deletes a Gaussian.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <optional>
#include <unordered_map>
#include <vector>

#include "ndtom/map/cell_index.h"
#include "ndtom/map/cell_stats.h"
#include "ndtom/map/gaussian.h"
#include "ndtom_eval/map_similarity.h"

namespace ndtom {

struct ErrorRefinementOptions {
  double resolution = 0.2;  ///< cell edge (Default: 0.2 m)
  double e_min = 5e-4;      ///< learning rate at occ = +o_max (Default: 5e-4)
  double e_max = 5e-2;      ///< learning rate at occ = −o_max (Default: 5e-2)
  double o_max = 10.0;      ///< occupancy clamp, log-odds (Default: 10)
  double p_hit = 0.6;       ///< p_o of Eq. 12, as NDT-OM (Default: 0.6)
  double p_miss = 0.49;     ///< p_e of Eq. 12, as NDT-OM (Default: 0.49)
  double min_range = 0.0;   ///< closer points are dropped (Default: 0 m)
  double max_range = std::numeric_limits<double>::infinity();  ///< farther points give a free
                                                               ///< ray up to here, no hit
};

/// Throws std::invalid_argument("<option>: <why>") on the first bad value.
void validate(const ErrorRefinementOptions& o);

/// ε(occ) of the ER update; occ is clamped to ±o_max first.
double errorRefinementRate(double occ, const ErrorRefinementOptions& o);

/// One ER step for point x (all in one frame, m and m²):
///   μ ← μ + ε(x − μ), then P ← P + ε((x − μ)(x − μ)ᵀ − P) with the new μ.
void refineGaussian(Eigen::Vector3d& mean, Eigen::Matrix3d& covariance, const Eigen::Vector3d& x,
                    double epsilon);

/// What one ER scan insertion did.
struct ErrorRefinementReport {
  size_t points_used = 0;        ///< hits merged into cells
  size_t points_rejected = 0;    ///< non-finite, out of the grid, too close, or beyond max_range
  size_t gaussians_created = 0;  ///< cells whose first Gaussian was made by this scan
  size_t points_refined = 0;     ///< points that went through the ER update
};

class ErrorRefinementMap {
 public:
  /// Throws std::invalid_argument if the options are invalid.
  explicit ErrorRefinementMap(const ErrorRefinementOptions& options = {});

  const ErrorRefinementOptions& options() const { return options_; }
  const GridGeometry& geometry() const { return geometry_; }

  /// Inserts one scan: points in the world frame seen from `sensor_origin` (throws
  /// std::invalid_argument if the origin is not finite or outside the grid).
  ErrorRefinementReport insertScan(const std::vector<Eigen::Vector3d>& points,
                                   const Eigen::Vector3d& sensor_origin);

  size_t numGaussians() const { return num_gaussians_; }
  /// World-frame Gaussian of a cell that has one (exact ER state, not regularised).
  std::optional<Gaussian> gaussian(const CellIndex& cell) const;
  /// occ of a cell holding a Gaussian.
  std::optional<double> occupancy(const CellIndex& cell) const;
  /// f(const Gaussian&) for every cell holding a Gaussian.
  template <class F>
  void forEachGaussian(F&& f) const;

 private:
  struct Cell {
    CellStats pending;  ///< points before the first Gaussian (cell-centred), exact
    bool has_gaussian = false;
    uint32_t n = 0;  ///< points absorbed, including the pending ones
    Eigen::Vector3d relative_mean = Eigen::Vector3d::Zero();  ///< relative to the cell centre
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    double occ = 0.0;
  };

  std::unordered_map<CellIndex, std::vector<Eigen::Vector3d>, CellIndexHash> hitsByCell(
      const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& origin,
      std::vector<Eigen::Vector3d>& ray_ends, ErrorRefinementReport& report) const;
  std::unordered_map<CellIndex, uint32_t, CellIndexHash> freeRaysThroughGaussians(
      const std::vector<Eigen::Vector3d>& ray_ends, const Eigen::Vector3d& origin) const;
  void updateHitCell(const CellIndex& index, const std::vector<Eigen::Vector3d>& relative,
                     ErrorRefinementReport& report);
  Gaussian toGaussian(const CellIndex& index, const Cell& cell) const;

  ErrorRefinementOptions options_;
  GridGeometry geometry_;
  std::unordered_map<CellIndex, Cell, CellIndexHash> cells_;
  size_t num_gaussians_ = 0;
};

/// The ER map's Gaussians for mapSimilarity, floored like the other maps' sets.
GaussianSet gaussianSetOf(const ErrorRefinementMap& map, const CovarianceFloor& floor = {});

// --- Template implementation ---------------------------------------------------------------

template <class F>
void ErrorRefinementMap::forEachGaussian(F&& f) const {
  for (const auto& [index, cell] : cells_)
    if (cell.has_gaussian) f(toGaussian(index, cell));
}

}  // namespace ndtom
