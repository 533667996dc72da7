// Scan-to-map registration on an NDT-OM: the pose of a scan (points in the sensor frame) in
// the map, from an initial guess, by Newton's method on an NDT score, coarse to fine over the
// map's exact coarsenings (paper Sec. III-B).
//
// - P2D (Magnusson 2009, ch. 6): each scan point against the Gaussians of its cell and the 26
//   around it, score −d1·exp(−d2/2·(y−μ)ᵀΣ⁻¹(y−μ)) (a Gaussian-plus-uniform outlier mixture
//   approximated by d1, d2).
// - D2D (Stoyanov et al., IJRR 2012): the scan's own NDT at the level's cell size, each of its
//   Gaussians against the map's around it, covariances summed: −d1·exp(−d2/2·mᵀ(RΣᵢRᵀ+Σⱼ)⁻¹m),
//   m = Rμᵢ + t − μⱼ.
// Only occupied cells take part (free space and vanished objects attract nothing). Exact
// gradient and Hessian; Newton steps on a Hessian made negative definite, then a backtracking
// line search with the Armijo condition (see doc/registration.md).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "ndtom/map/ndt_map.h"
#include "ndtom/registration/map_pyramid.h"

namespace ndtom {

enum class RegistrationMethod { P2D = 0, D2D = 1 };

const char* toString(RegistrationMethod method);
/// Accepts "p2d"/"P2D" and "d2d"/"D2D"; throws std::invalid_argument otherwise.
RegistrationMethod registrationMethodFromString(const std::string& text);

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct RegistrationOptions {
  RegistrationMethod method = RegistrationMethod::P2D;
  /// Levels, coarse to fine, as multiples of the map's cell (Default: 16 8 4 2 1: 3.2 m to
  /// 0.2 m cells on a 0.2 m map). The coarse levels widen the basin of convergence.
  std::vector<int> level_factors = {16, 8, 4, 2, 1};
  /// Expected fraction of outliers in the score's mixture (Default: 0.55, as PCL and ndt_omp).
  double outlier_ratio = 0.55;
  /// Newton iterations per level at most (Default: 30).
  int max_iterations = 30;
  /// A level ends when a step moves the sensor less than this (Default: 1e-4 m) and turns it
  /// less than rotation_epsilon (Default: 1e-4 rad, 0.006°).
  double translation_epsilon = 1e-4;
  double rotation_epsilon = 1e-4;
  /// Scan points used: distance from the sensor in [min_range, max_range] (Default: 0, inf).
  double min_range = 0.0;
  double max_range = std::numeric_limits<double>::infinity();
  /// P2D: the scan is reduced to the centroid of its points in voxels of this fraction of
  /// the level's cell (Default: 0.5) ...
  double voxel_ratio = 0.5;
  /// ... and to at most this many of them per level, evenly spread (Default: 6000).
  size_t max_points = 6000;
  /// Verdict: of the scan points (P2D) or scan Gaussians (D2D) the map can judge, the
  /// fraction within 3σ of a map Gaussian at the finest level must reach this (Default: 0.4).
  /// With occupancy, the map judges what matches, or lands in a cell it has seen free or one
  /// with a Gaussian; what lands where it has never looked (or in an occupied cell too thin
  /// for a Gaussian) is neither a match nor a miss, so a scan that overlaps the map in part is
  /// placed. Without occupancy every item is judged ...
  double min_matched_fraction = 0.4;
  /// ... and the judged fraction of the scan must reach this: below it, too little of the
  /// scan overlaps what the map knows to tell a right pose from a wrong one (Default: 0.15).
  double min_judged_fraction = 0.15;
  /// ... and at most this fraction of them may lie in open free space: cells the map has seen
  /// free (log-odds < 0) with no occupied cell among the 26 around them. A scan slid along a
  /// repetitive structure puts its points there, a right pose only those of moving objects
  /// (Default: 0.05; 1 disables the check).
  double max_free_fraction = 0.05;
  /// Only x, y and the rotation about the map's z axis change; z, roll and pitch stay as
  /// guessed: for 2D scans and robots on flat ground (Default: false).
  bool planar = false;
  /// Only z and the rotations about the map's x and y axes change; x, y and yaw stay as
  /// guessed: levelling a pose on the ground (the online mapper's second pass, on every ground
  /// point). Not with `planar` (Default: false).
  bool level_only = false;
  /// Threads over points; the result is the same for any count (Default: 1).
  int threads = 1;
  /// Not an option: where to add the time of each stage of align(), or null (Default). The
  /// pose does not depend on it.
  StageProfile* profile = nullptr;
};

/// Throws std::invalid_argument("<option> = <value>: <why>") on the first bad value.
void validate(const RegistrationOptions& options);

struct LevelReport {
  double resolution = 0;  ///< of the map level (m)
  int iterations = 0;     ///< Newton steps taken
  int evaluations = 0;    ///< score evaluations (line search trials included)
  size_t scan_items = 0;  ///< scan points (P2D) or scan Gaussians (D2D) used
  double score = 0;       ///< at the level's end, per scan item
  double matched_fraction = 0;
  bool converged = false;  ///< a step fell below the epsilons (else: iteration limit)
  double seconds = 0;
};

struct RegistrationResult {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< sensor -> map
  /// Of the pose's error δ = (v, ω): pose = (Exp(ω)·R, t + v), i.e. a translation and a
  /// rotation vector in the map frame turning about the sensor (m², rad²). Gauss-Newton
  /// information of the matched terms at the finest level, scaled by their residual; zero
  /// rows and columns for what `planar` keeps fixed.
  Matrix6d covariance = Matrix6d::Identity();
  std::vector<LevelReport> levels;  ///< coarse to fine
  double score = 0;                 ///< finest level's score per scan item
  double matched_fraction = 0;      ///< finest level's, of the judged items
  double judged_fraction = 0;       ///< of the finest level's items, in space the map knows
  double free_fraction = 0;         ///< of the finest level's scan items, in open free space
  /// The verdict: the finest level converged, the map could judge enough of the scan and
  /// matched enough of that, and little of it lies in free space. When false, `pose` is the last estimate and `failure` says why.
  bool converged = false;
  /// Refused by the free-space check alone: the pose fits the map's Gaussians, but part of
  /// the scan lies where the map saw free space (something new there, or a map that
  /// contradicts itself, as where drifting odometry comes back to streets it mapped long ago).
  bool refused_for_free_space_only = false;
  std::string failure;
  double seconds = 0;  ///< the whole call, pyramid (re)building included
  bool pyramid_rebuilt = false;
};

class NdtRegistration {
 public:
  /// Throws std::invalid_argument on bad options.
  explicit NdtRegistration(const RegistrationOptions& options = {});
  ~NdtRegistration();
  NdtRegistration(NdtRegistration&&) noexcept;
  NdtRegistration& operator=(NdtRegistration&&) noexcept;

  const RegistrationOptions& options() const { return options_; }
  /// Throws std::invalid_argument on bad options; the pyramid is rebuilt if levels change.
  void setOptions(const RegistrationOptions& options);

  /// The pose of `scan` (sensor frame) in `map`, from `guess` (sensor -> map). The map's
  /// pyramid is built on first use and kept until the map's revision() changes. Throws
  /// std::invalid_argument for a non-finite or non-rigid guess, an empty map (no occupied
  /// Gaussian) or a scan without a usable point; nothing is cached then.
  RegistrationResult align(const NdtMap& map, const std::vector<Eigen::Vector3d>& scan,
                           const Eigen::Isometry3d& guess);
  /// The same on levels [begin, end) of the pyramid only (coarse to fine; end is clamped to
  /// its size): the coarse ones for a cheap first look (global localization sorts its
  /// hypotheses so), the fine ones where the guess is already close (tracking). The verdict is
  /// the last level's.
  struct Levels {
    size_t begin = 0;
    size_t end = SIZE_MAX;
  };
  RegistrationResult align(const NdtMap& map, const std::vector<Eigen::Vector3d>& scan,
                           const Eigen::Isometry3d& guess, Levels levels);

  /// The pyramid used by the last call (null before the first).
  std::shared_ptr<const MapPyramid> pyramid() const { return pyramid_; }
  /// The pyramid for `map`: the pinned one or the cached one if it is for the map as it is,
  /// else a new one.
  std::shared_ptr<const MapPyramid> pyramidFor(const NdtMap& map);
  /// Registers against `pyramid` (its level factors must be the options') while the map
  /// given to align() has revision `revision`, instead of building one from that map: an
  /// online mapper's pyramid of the map's region around the sensor, kept as the map grows.
  /// The verdict still judges against the map itself. A null pyramid unpins.
  void pinPyramid(std::shared_ptr<const MapPyramid> pyramid, uint64_t revision);

  /// Registers on the pyramid's first `count` levels only (coarse to fine; SIZE_MAX: all, the
  /// default): the finest then in use is the last of them, for every align() and its
  /// verdict. ScanPlacer retries a scan without the finest level so.
  void setLevelsInUse(size_t count);
  size_t levelsInUse() const { return levels_in_use_; }

 private:
  struct State;  // the worker pool, and the last scan as the levels see it
  RegistrationOptions options_;
  std::shared_ptr<const MapPyramid> pyramid_;
  std::shared_ptr<const MapPyramid> pinned_;
  uint64_t pinned_revision_ = 0;
  size_t levels_in_use_ = SIZE_MAX;
  std::unique_ptr<State> state_;
};

}  // namespace ndtom
