#include "ndtom/registration/registration.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "registration/ndt_objective.h"
#include "registration/newton_search.h"
#include "registration/scan_levels.h"
#include "registration/usable_points.h"
#include "registration/verdict.h"
#include "support/elapsed.h"
#include "support/option_error.h"
#include "support/parallel.h"
#include "support/stage_clock.h"

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

constexpr uint64_t kFnvOffsetBasis = 0xcbf29ce484222325ULL;

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
/// The points are hashed in fixed chunks on the pool's threads, then the chunks' hashes in
/// order: the same key for any thread count.
uint64_t scanKey(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& resolutions,
                 const RegistrationOptions& o, const Regularization& reg, Threads threads) {
  constexpr size_t kChunkPoints = 4096;
  const size_t chunks = (points.size() + kChunkPoints - 1) / kChunkPoints;
  std::vector<uint64_t> chunk_hashes(chunks, kFnvOffsetBasis);
  const size_t parts = threads.forItems(chunks, 1);
  threads.pool.run(parts, [&](size_t t) {
    const auto [first, last] = partRange(chunks, parts, t);
    for (size_t c = first; c < last; ++c) {
      const size_t begin = c * kChunkPoints, end = std::min(points.size(), begin + kChunkPoints);
      mix(chunk_hashes[c], points.data() + begin, (end - begin) * sizeof(Eigen::Vector3d));
    }
  });
  uint64_t h = kFnvOffsetBasis;
  mix(h, chunk_hashes.data(), chunk_hashes.size() * sizeof(uint64_t));
  mix(h, resolutions.data(), resolutions.size() * sizeof(double));
  const int method = int(o.method);
  mix(h, &method, sizeof(method));
  mix(h, &o.voxel_ratio, sizeof(double));
  mix(h, &o.max_points, sizeof(size_t));
  mix(h, &reg.min_eigen_ratio, sizeof(double));
  mix(h, &reg.min_eigen_abs, sizeof(double));
  return h | 1;  // never 0, the empty cache's key
}

/// The pyramid's levels a call registers on: [begin, end) clamped, at least the finest.
struct LevelSpan {
  size_t begin = 0;
  std::vector<double> resolutions;  ///< of each level, coarse to fine (m)
};
LevelSpan levelSpan(const MapPyramid& pyramid, size_t begin, size_t end) {
  if (pyramid.level(pyramid.size() - 1).empty())
    throw std::invalid_argument("registration: the map has no occupied cell with a Gaussian");
  LevelSpan span;
  end = std::min(end, pyramid.size());
  span.begin = std::min(begin, end - 1);  // at least one level
  for (size_t l = span.begin; l < end; ++l) span.resolutions.push_back(pyramid.resolution(l));
  return span;
}

/// Newton's method on one level from `pose`, which it moves; `coarseness` (level factor over
/// the finest's) scales the epsilons.
LevelReport registerLevel(const registration::NdtObjective& objective, size_t scan_items,
                          double resolution, double coarseness, const RegistrationOptions& o,
                          Eigen::Isometry3d& pose) {
  const auto start = Clock::now();
  registration::NewtonSettings settings;
  settings.max_iterations = o.max_iterations;
  // Coarse levels only need to bring the pose within the next level's reach: their
  // epsilons grow with the square of their coarseness (256x at 16x: 2.6 cm, 1.5 deg).
  settings.translation_epsilon = o.translation_epsilon * coarseness * coarseness;
  settings.rotation_epsilon = o.rotation_epsilon * coarseness * coarseness;
  settings.max_translation_step = resolution;
  settings.free = registration::freeParameters(o.planar, o.level_only);
  LevelReport report;
  report.resolution = resolution;
  report.scan_items = scan_items;
  if (scan_items > 0) {
    const registration::NewtonOutcome outcome =
        registration::newtonSearch(objective, pose, settings);
    report.iterations = outcome.iterations;
    report.evaluations = outcome.evaluations;
    report.converged = outcome.converged;
    report.score = outcome.value.score / double(outcome.value.items);
    report.matched_fraction = double(outcome.value.matched) / double(outcome.value.items);
  }
  report.seconds = secondsSince(start);
  return report;
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
  if (!(o.min_judged_fraction >= 0 && o.min_judged_fraction <= 1))
    failOption("min_judged_fraction", o.min_judged_fraction, "must be in [0, 1]");
  if (!(o.max_free_fraction >= 0 && o.max_free_fraction <= 1))
    failOption("max_free_fraction", o.max_free_fraction, "must be in [0, 1]");
  if (o.planar && o.level_only)
    throw std::invalid_argument("planar and level_only: at most one of them (they fix what the other frees)");
  if (!(o.threads >= 1 && o.threads <= ScanOptions::kMaxThreads))
    failOption("threads", o.threads, "must be in [1, 256]");
}

struct NdtRegistration::State {
  WorkerPool pool;
  /// The scan levels of the last call, kept for calls with the same scan, options and
  /// levels (retries, global localization's hypotheses): building them sorts every point.
  uint64_t scan_key = 0;
  std::vector<registration::ScanLevel> levels;

  /// The scan's levels at `resolutions` (coarse to fine), from the cache if they are there.
  const std::vector<registration::ScanLevel>& levelsFor(const NdtMap& map,
                                                        const std::vector<Eigen::Vector3d>& scan,
                                                        const std::vector<double>& resolutions,
                                                        const RegistrationOptions& o) {
    const double finest_voxel =
        resolutions.back() * (o.method == RegistrationMethod::P2D ? o.voxel_ratio : 1.0);
    const Threads threads{pool, size_t(o.threads)};
    const std::vector<Eigen::Vector3d> points =
        registration::usablePoints(scan, o.min_range, o.max_range, finest_voxel, threads);
    if (points.empty())
      throw std::invalid_argument("registration: the scan has no finite point within [" +
                                  std::to_string(o.min_range) + ", " + std::to_string(o.max_range) +
                                  "] m of the sensor");
    const uint64_t key = scanKey(points, resolutions, o, map.options().regularization, threads);
    if (key != scan_key || levels.empty()) {
      levels = registration::buildScanLevels(points, resolutions, o, map.options().regularization,
                                             threads);
      scan_key = key;
    }
    return levels;
  }
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
  if (options.level_factors != options_.level_factors) {
    pyramid_.reset();
    pinned_.reset();
  }
  options_ = options;
}

void NdtRegistration::pinPyramid(std::shared_ptr<const MapPyramid> pyramid, uint64_t revision) {
  if (pyramid && pyramid->factors() != options_.level_factors)
    throw std::invalid_argument("pinPyramid: the pyramid's levels are not the options' level_factors");
  pinned_ = std::move(pyramid);
  pinned_revision_ = revision;
}

void NdtRegistration::setLevelsInUse(size_t count) {
  if (count == 0) throw std::invalid_argument("setLevelsInUse: at least one level");
  levels_in_use_ = count;
}

std::shared_ptr<const MapPyramid> NdtRegistration::pyramidFor(const NdtMap& map) {
  if (pinned_ && pinned_revision_ == map.revision()) return pinned_;
  if (pyramid_ && pyramid_->revision() == map.revision() &&
      pyramid_->factors() == options_.level_factors &&
      pyramid_->level(pyramid_->size() - 1).geometry().resolution() == map.geometry().resolution())
    return pyramid_;
  return std::make_shared<const MapPyramid>(map, options_.level_factors, options_.threads);
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
  StageClock clock(o.profile);
  clock.next("setup");
  RegistrationResult result;
  result.pose = rigidGuess(guess);

  // The map's levels and the scan's, coarse to fine.
  clock.next("pyramid");
  const auto pyramid = pyramidFor(map);
  result.pyramid_rebuilt = pyramid != pyramid_;
  const size_t in_use = std::min(pyramid->size(), levels_in_use_);
  const LevelSpan span = levelSpan(*pyramid, range.begin, std::min(range.end, in_use));
  clock.next("scan levels");
  const std::vector<ScanLevel>& levels = state_->levelsFor(map, scan, span.resolutions, o);
  pyramid_ = pyramid;

  // Newton's method on each level, from the pose the coarser one reached; the second level
  // starts from the guess instead if it scores the guess higher. Where the scene holds a
  // direction loosely (along a street), the coarsest level's optimum can lie farther from the
  // truth than the next level reaches (the 3.2 m level moved a well predicted city scan 1.6 m
  // back; the 1.6 m level then held it 1 m off, where it converges from the guess). Finer
  // levels asking the same kept decimetre errors of the prediction (ndtom-localize: scans a
  // constant-velocity prediction missed by 0.1-0.2 m stayed there on the 0.2 m level).
  clock.next("newton");
  const Eigen::Isometry3d guess_pose = result.pose;
  std::vector<NdtObjective> objectives;
  objectives.reserve(levels.size());
  for (size_t l = 0; l < levels.size(); ++l) {
    const size_t level = span.begin + l;  // in the pyramid
    const double res = span.resolutions[l];
    objectives.emplace_back(pyramid->level(level), levels[l], o.method,
                            scoreConstants(res, o.outlier_ratio), state_->pool, o.threads);
    if (l == 1 && objectives.back().evaluate(guess_pose, false).score >
                      objectives.back().evaluate(result.pose, false).score)
      result.pose = guess_pose;
    const double coarseness = double(pyramid->factor(level)) / pyramid->factor(in_use - 1);
    result.levels.push_back(
        registerLevel(objectives.back(), levels[l].size(), res, coarseness, o, result.pose));
  }

  // The finest level's fit, the pose's covariance, and the verdict.
  clock.next("verdict");
  const LevelReport& last = result.levels.back();
  result.score = last.score;
  const SpaceFractions space = spaceFractions(map, objectives.back(), levels.back(), result.pose,
                                                 {state_->pool, size_t(o.threads)});
  result.free_fraction = space.free;
  result.judged_fraction = 1 - space.unknown;
  // Matched items are judged ones: of those, the matched share.
  result.matched_fraction =
      result.judged_fraction > 0 ? std::min(1.0, last.matched_fraction / result.judged_fraction)
                                 : 0.0;
  const PoseCovariance covariance =
      poseCovariance(objectives.back(), result.pose, freeParameters(o.planar, o.level_only));
  result.covariance = covariance.covariance;
  result.failure = verdict(result, covariance.constrained, o);
  result.converged = result.failure.empty();
  result.refused_for_free_space_only =
      !result.converged && verdict(result, covariance.constrained, o, false).empty();
  clock.stop();
  result.seconds = secondsSince(start);
  return result;
}

}  // namespace ndtom
