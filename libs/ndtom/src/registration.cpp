#include "ndtom/registration.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "elapsed.h"
#include "option_error.h"
#include "parallel.h"
#include "registration/ndt_objective.h"
#include "registration/newton_search.h"
#include "registration/scan_levels.h"

namespace ndtom {
namespace {

/// The guess as a rigid transform: finite, its rotation orthonormal with determinant +1
/// (re-orthonormalised within 1e-6, as float round trips leave it).
Eigen::Isometry3d rigidGuess(const Eigen::Isometry3d& guess) {
  if (!guess.matrix().allFinite())
    throw std::invalid_argument("registration: the initial guess is not finite");
  const Eigen::Matrix3d r = guess.linear();
  if (!((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() < 1e-6 && r.determinant() > 0))
    throw std::invalid_argument(
        "registration: the initial guess is not a rigid motion (rotation not orthonormal with "
        "determinant +1)");
  Eigen::Isometry3d out = guess;
  out.linear() = Eigen::Quaterniond(r).normalized().toRotationMatrix();
  return out;
}

/// Whether `cell` is known free and none of the 26 around it is occupied: open space, where a
/// right pose puts only moving objects. (A free cell beside a surface is no evidence: rays
/// that grazed the surface freed it, and the scan's noise reaches it.)
bool inOpenFreeSpace(const NdtMap& map, const CellIndex& cell) {
  const auto c = map.cell(cell);
  if (!c || !(c->logodds < 0.f)) return false;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const auto n = map.cell({cell.x + dx, cell.y + dy, cell.z + dz});
        if (n && n->logodds > 0.f) return false;
      }
  return true;
}

/// The fraction of the level's scan items (points or Gaussian means) that `pose` puts in open
/// free space; 0 for a map without occupancy.
double freeFraction(const NdtMap& map, const registration::ScanLevel& level,
                    const Eigen::Isometry3d& pose) {
  if (!map.options().occupancy.enabled || level.size() == 0) return 0;
  size_t free = 0;
  auto count = [&](const Eigen::Vector3d& item) {
    const Eigen::Vector3d p = pose * item;
    free += map.geometry().inRange(p) && inOpenFreeSpace(map, map.geometry().cellOf(p));
  };
  for (const Eigen::Vector3d& p : level.points) count(p);
  for (const registration::ScanGaussian& g : level.gaussians) count(g.mean);
  return double(free) / double(level.size());
}

/// Finite points within the range limits whose cells the finest grid can index.
std::vector<Eigen::Vector3d> usablePoints(const std::vector<Eigen::Vector3d>& scan,
                                          const RegistrationOptions& o, double finest_cell) {
  const GridGeometry grid(finest_cell);
  std::vector<Eigen::Vector3d> out;
  out.reserve(scan.size());
  for (const Eigen::Vector3d& p : scan) {
    if (!grid.inRange(p)) continue;  // also drops NaN and inf
    const double range = p.norm();
    if (range >= o.min_range && range <= o.max_range) out.push_back(p);
  }
  return out;
}

// FNV-1a over 8-byte words (then the tail bytes): fast enough to hash a scan per call.
void mix(uint64_t& h, const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  size_t i = 0;
  for (; i + 8 <= bytes; i += 8) {
    uint64_t word;
    std::memcpy(&word, p + i, 8);
    h = (h ^ word) * 0x100000001b3ULL;
  }
  for (; i < bytes; ++i) h = (h ^ p[i]) * 0x100000001b3ULL;
}

/// What the scan levels depend on, hashed: the points and every option that shapes them.
uint64_t scanKey(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& resolutions,
                 const RegistrationOptions& o, const Regularization& reg) {
  uint64_t h = 0xcbf29ce484222325ULL;
  mix(h, points.data(), points.size() * sizeof(Eigen::Vector3d));
  mix(h, resolutions.data(), resolutions.size() * sizeof(double));
  const int method = int(o.method);
  mix(h, &method, sizeof(method));
  mix(h, &o.voxel_ratio, sizeof(double));
  mix(h, &o.max_points, sizeof(size_t));
  mix(h, &reg.min_eigen_ratio, sizeof(double));
  mix(h, &reg.min_eigen_abs, sizeof(double));
  return h | 1;  // never 0, the empty cache's key
}

}  // namespace

const char* toString(RegistrationMethod method) {
  return method == RegistrationMethod::D2D ? "d2d" : "p2d";
}

RegistrationMethod registrationMethodFromString(const std::string& text) {
  if (text == "p2d" || text == "P2D") return RegistrationMethod::P2D;
  if (text == "d2d" || text == "D2D") return RegistrationMethod::D2D;
  throw std::invalid_argument("method = " + text + ": expected p2d or d2d");
}

void validate(const RegistrationOptions& o) {
  if (o.method != RegistrationMethod::P2D && o.method != RegistrationMethod::D2D)
    failOption("method", double(int(o.method)), "unknown method");
  if (o.level_factors.empty()) throw std::invalid_argument("level_factors: none given");
  for (size_t i = 0; i < o.level_factors.size(); ++i) {
    if (o.level_factors[i] < 1 || o.level_factors[i] > 1024)
      failOption("level_factors", o.level_factors[i], "each must be in [1, 1024]");
    if (i > 0 && o.level_factors[i] >= o.level_factors[i - 1])
      failOption("level_factors", o.level_factors[i], "must decrease: coarse to fine");
  }
  if (!(o.outlier_ratio > 0 && o.outlier_ratio < 1))
    failOption("outlier_ratio", o.outlier_ratio, "must be in (0, 1)");
  if (!(o.max_iterations >= 1 && o.max_iterations <= 1000))
    failOption("max_iterations", o.max_iterations, "must be in [1, 1000]");
  if (!(o.translation_epsilon > 0 && std::isfinite(o.translation_epsilon)))
    failOption("translation_epsilon", o.translation_epsilon, "must be finite and > 0");
  if (!(o.rotation_epsilon > 0 && std::isfinite(o.rotation_epsilon)))
    failOption("rotation_epsilon", o.rotation_epsilon, "must be finite and > 0");
  if (!(o.min_range >= 0 && std::isfinite(o.min_range)))
    failOption("min_range", o.min_range, "must be finite and >= 0");
  if (!(o.max_range > o.min_range)) failOption("max_range", o.max_range, "must be > min_range");
  if (!(o.voxel_ratio >= 0.05 && o.voxel_ratio <= 4))
    failOption("voxel_ratio", o.voxel_ratio, "must be in [0.05, 4]");
  if (o.max_points < 10) failOption("max_points", double(o.max_points), "must be >= 10");
  if (!(o.min_matched_fraction >= 0 && o.min_matched_fraction <= 1))
    failOption("min_matched_fraction", o.min_matched_fraction, "must be in [0, 1]");
  if (!(o.max_free_fraction >= 0 && o.max_free_fraction <= 1))
    failOption("max_free_fraction", o.max_free_fraction, "must be in [0, 1]");
  if (!(o.threads >= 1 && o.threads <= InsertOptions::kMaxThreads))
    failOption("threads", o.threads, "must be in [1, 256]");
}

struct NdtRegistration::State {
  WorkerPool pool;
  /// The scan levels of the last call, kept for calls with the same scan, options and
  /// levels (retries, global localization's hypotheses): building them sorts every point.
  uint64_t scan_key = 0;
  std::vector<registration::ScanLevel> levels;
};

NdtRegistration::NdtRegistration(const RegistrationOptions& options)
    : options_(options), state_(std::make_unique<State>()) {
  validate(options_);
}
NdtRegistration::~NdtRegistration() = default;
NdtRegistration::NdtRegistration(NdtRegistration&&) noexcept = default;
NdtRegistration& NdtRegistration::operator=(NdtRegistration&&) noexcept = default;

void NdtRegistration::setOptions(const RegistrationOptions& options) {
  validate(options);
  if (options.level_factors != options_.level_factors) pyramid_.reset();
  options_ = options;
}

std::shared_ptr<const MapPyramid> NdtRegistration::pyramidFor(const NdtMap& map) {
  if (pyramid_ && pyramid_->revision() == map.revision() &&
      pyramid_->factors() == options_.level_factors &&
      pyramid_->level(pyramid_->size() - 1).geometry().resolution() == map.geometry().resolution())
    return pyramid_;
  return std::make_shared<const MapPyramid>(map, options_.level_factors);
}

RegistrationResult NdtRegistration::align(const NdtMap& map,
                                          const std::vector<Eigen::Vector3d>& scan,
                                          const Eigen::Isometry3d& guess) {
  return align(map, scan, guess, Levels{});
}

RegistrationResult NdtRegistration::align(const NdtMap& map,
                                          const std::vector<Eigen::Vector3d>& scan,
                                          const Eigen::Isometry3d& guess, Levels range) {
  using namespace registration;
  const auto start = Clock::now();
  const RegistrationOptions& o = options_;
  RegistrationResult result;
  result.pose = rigidGuess(guess);

  const auto pyramid = pyramidFor(map);
  result.pyramid_rebuilt = pyramid != pyramid_;
  if (pyramid->level(pyramid->size() - 1).empty())
    throw std::invalid_argument("registration: the map has no occupied cell with a Gaussian");
  const size_t end = std::min(range.end, pyramid->size());
  const size_t begin = std::min(range.begin, end - 1);  // at least one level
  std::vector<double> resolutions;
  for (size_t l = begin; l < end; ++l) resolutions.push_back(pyramid->resolution(l));
  const double finest_voxel =
      resolutions.back() * (o.method == RegistrationMethod::P2D ? o.voxel_ratio : 1.0);
  const std::vector<Eigen::Vector3d> points = usablePoints(scan, o, finest_voxel);
  if (points.empty())
    throw std::invalid_argument("registration: the scan has no finite point within [" +
                                std::to_string(o.min_range) + ", " + std::to_string(o.max_range) +
                                "] m of the sensor");
  pyramid_ = pyramid;
  const uint64_t key = scanKey(points, resolutions, o, map.options().regularization);
  if (key != state_->scan_key || state_->levels.empty()) {
    state_->levels = buildScanLevels(points, resolutions, o, map.options().regularization);
    state_->scan_key = key;
  }
  const std::vector<ScanLevel>& levels = state_->levels;

  const NdtObjective* finest = nullptr;
  std::vector<NdtObjective> objectives;
  objectives.reserve(levels.size());
  for (size_t l = 0; l < levels.size(); ++l) {
    const auto level_start = Clock::now();
    const double res = resolutions[l];
    const size_t level = begin + l;  // in the pyramid
    objectives.emplace_back(pyramid->level(level), levels[l], o.method,
                            scoreConstants(res, o.outlier_ratio), state_->pool, o.threads);
    finest = &objectives.back();
    NewtonSettings settings;
    settings.max_iterations = o.max_iterations;
    // Coarse levels only need to bring the pose within the next level's reach: their
    // epsilons grow with the square of their coarseness (256x at 16x: 2.6 cm, 1.5 deg).
    const double coarseness =
        double(pyramid->factor(level)) / pyramid->factor(pyramid->size() - 1);
    settings.translation_epsilon = o.translation_epsilon * coarseness * coarseness;
    settings.rotation_epsilon = o.rotation_epsilon * coarseness * coarseness;
    settings.max_translation_step = res;
    settings.free = freeParameters(o.planar);
    LevelReport report;
    report.resolution = res;
    report.scan_items = levels[l].size();
    if (levels[l].size() > 0) {
      const NewtonOutcome outcome = newtonSearch(objectives.back(), result.pose, settings);
      report.iterations = outcome.iterations;
      report.evaluations = outcome.evaluations;
      report.converged = outcome.converged;
      report.score = outcome.value.score / double(outcome.value.items);
      report.matched_fraction = double(outcome.value.matched) / double(outcome.value.items);
    }
    report.seconds = secondsSince(level_start);
    result.levels.push_back(report);
  }

  const LevelReport& last = result.levels.back();
  result.score = last.score;
  result.matched_fraction = last.matched_fraction;
  result.free_fraction = freeFraction(map, levels.back(), result.pose);
  // Covariance over the free parameters; fixed ones get zero rows and columns.
  const std::array<bool, 6> free = freeParameters(o.planar);
  const PoseInformation info = finest->information(result.pose);
  // (Fixed parameters get a curvature on the scale of the others: out of the rank test.)
  const double typical = std::max(info.information.diagonal().maxCoeff(), 1e-300);
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(restrictTo(info.information, free, typical));
  const size_t free_count = size_t(std::count(free.begin(), free.end(), true));
  const bool constrained =
      info.terms > free_count && eig.eigenvalues()[0] > 1e-9 * eig.eigenvalues()[5];
  if (constrained) {
    // Residuals as the map's Gaussians predict give χ² ≈ 3 per term: a scale near 1.
    const double scale = info.chi2 / double(3 * info.terms - free_count);
    result.covariance =
        restrictTo(scale * eig.eigenvectors() * eig.eigenvalues().cwiseInverse().asDiagonal() *
                       eig.eigenvectors().transpose(),
                   free, 0.0);
  } else {
    result.covariance = restrictTo(Matrix6d::Identity() * 1e6, free, 0.0);
  }

  if (!last.converged) {
    result.failure =
        "the finest level did not converge in " + std::to_string(o.max_iterations) + " iterations";
  } else if (last.matched_fraction < o.min_matched_fraction) {
    std::ostringstream why;
    why << "only " << last.matched_fraction << " of the scan matched the map (min_matched_fraction "
        << o.min_matched_fraction << ")";
    result.failure = why.str();
  } else if (result.free_fraction > o.max_free_fraction) {
    std::ostringstream why;
    why << result.free_fraction << " of the scan lies in open space the map has seen free "
        << "(max_free_fraction " << o.max_free_fraction << ")";
    result.failure = why.str();
  } else if (!constrained) {
    result.failure = "the matched part of the scan does not constrain all six degrees of freedom";
  }
  result.converged = result.failure.empty();
  result.seconds = secondsSince(start);
  return result;
}

}  // namespace ndtom
