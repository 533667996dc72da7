// The observation likelihood of NDT-MCL (Saarinen, Andreasson, Stoyanov, Lilienthal,
// "Normal Distributions Transform Monte-Carlo Localization (NDT-MCL)", IROS 2013): a
// particle filter scores each particle by the scan's own NDT against the map's.
//
// Once per observation the scan is reduced to the Gaussians of its points in cells of its
// own edge, in the sensor frame, and only `max_gaussians` of them are kept, taken in turn
// from the cells facing x, y and z, most points first (normal-space sampling, so that every
// direction stays constrained; buildScanNdt). Once per map state the map's Gaussians are put in a
// table by cell (NdtMclMap). Then, per particle pose (R, t), each scan Gaussian i is moved into the
// map and scored against the map Gaussian j of the cell its mean falls in, found by direct
// lookup (no search), with the covariances summed:
//
//   l_i = (Rμ_i + t − μ_j)ᵀ (RΣ_iRᵀ + Σ_j)⁻¹ (Rμ_i + t − μ_j)
//   s_i = c + (1 − c)·exp(−d·l_i / 2)          (s_i = c when the cell has no Gaussian)
//   log L = Σ_i log s_i
//
// NDT-MCL's code sums s_i (c = 0.1, d = 0.05) and uses the sum as the weight; here the
// terms multiply, as independent measurements do and as MRPT's filters expect of a
// log-likelihood, so d need not be that small to keep weights from collapsing (a scale on
// log L does that). A pose where the scan meets no map Gaussian scores the floor
// |scan|·log c, the lowest score there is and finite; an empty scan scores 0 anywhere.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ndtom/map/cell_index.h"
#include "ndtom/map/gaussian.h"
#include "ndtom/map/ndt_map.h"

namespace ndtom {

struct ScanNdtOptions {
  /// Edge of the scan's cells (m) (Default: 0.4). NDT-MCL scores against map cells of the
  /// same edge; a finer map level works too (a scan Gaussian is then matched to the piece of
  /// surface its mean falls on).
  double cell_size = 0.4;
  /// Scan Gaussians kept (Default: 300), in turn from the cells facing x, y and z, most points
  /// first. The per-particle cost grows with it; the scan NDT is built once per observation.
  size_t max_gaussians = 300;
  /// Eigenvalue floor of the scan's covariances (Default: as the map's).
  Regularization regularization;
};

/// Throws std::invalid_argument naming the bad option.
void validate(const ScanNdtOptions& options);

/// A Gaussian as NDT-MCL uses it: the covariance regularised, stored as its upper triangle
/// (xx, xy, xz, yy, yz, zz), all that the per-particle rotation and sum need.
struct MclGaussian {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();  ///< (m)
  double cov[6] = {0, 0, 0, 0, 0, 0};              ///< (m²)
  uint32_t n = 0;                                  ///< points behind it
};

struct ScanNdt {
  /// The kept ones (sensor frame), in cell order: consecutive ones fall in nearby map cells.
  std::vector<MclGaussian> gaussians;
  double cell_size = 0;            ///< (m)
  size_t points = 0;               ///< finite points grouped
  size_t cells_with_gaussian = 0;  ///< before keeping max_gaussians of them
};

/// The scan's NDT from points in the sensor frame; non-finite points are skipped. Throws on
/// bad options.
ScanNdt buildScanNdt(const std::vector<Eigen::Vector3d>& points, const ScanNdtOptions& options);

/// The Gaussians of a map's occupied cells (all of them without occupancy), regularised as
/// the map's options say, in one open-addressing table by cell: a lookup is a hash and a
/// probe or two in one array, where a GaussianLookup goes through a node-based hash map
/// and a block, which dominated a particle's score. Immutable: concurrent queries are safe.
class NdtMclMap {
 public:
  NdtMclMap() = default;
  /// The map at its own resolution: pass map.coarsened(k) for cells k times larger.
  explicit NdtMclMap(const NdtMap& map);

  const GridGeometry& geometry() const { return geometry_; }
  size_t size() const { return gaussians_.size(); }
  bool empty() const { return gaussians_.empty(); }
  /// The Gaussian of the cell holding `point` (world frame); nullptr if none, or if the
  /// point is not finite or out of range.
  const MclGaussian* findAt(const Eigen::Vector3d& point) const;

 private:
  struct Slot {
    CellIndex cell;
    uint32_t index = kEmpty;  ///< into gaussians_
  };
  static constexpr uint32_t kEmpty = UINT32_MAX;

  GridGeometry geometry_;
  std::vector<MclGaussian> gaussians_;               ///< in cell order
  std::vector<Slot> slots_ = std::vector<Slot>(16);  ///< power-of-two size, at most half full
};

struct NdtMclOptions {
  /// c: a scan Gaussian's likelihood never drops below this, in (0, 1) (Default: 0.1, as
  /// NDT-MCL).
  double outlier_likelihood = 0.1;
  /// d: how fast a pair's likelihood falls with l, > 0 (Default: 1, a plain Gaussian).
  double exponent_scale = 1.0;
};

/// Throws std::invalid_argument naming the bad option.
void validate(const NdtMclOptions& options);

struct NdtMclScore {
  double log_likelihood = 0;  ///< Σ log s_i (≤ 0)
  size_t scored = 0;          ///< scan Gaussians
  size_t matched = 0;         ///< of those, the ones whose cell has a map Gaussian
};

/// Scores `scan` at `pose` (sensor -> map) against `map`, whose cells should have the scan's
/// cell size. Does not validate `options` (it runs once per particle): validate them first.
NdtMclScore ndtMclLikelihood(const NdtMclMap& map, const ScanNdt& scan,
                             const Eigen::Isometry3d& pose, const NdtMclOptions& options);

}  // namespace ndtom
