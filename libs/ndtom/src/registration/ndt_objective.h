// The NDT score of a scan level against a map level at a pose, with its exact gradient and
// Hessian in the local parameters of pose_increment.h. Summed over fixed chunks of the scan
// in a fixed order, so the value does not depend on the number of threads.
#pragma once

#include <Eigen/Geometry>

#include "ndtom/matching/gaussian_lookup.h"
#include "ndtom/registration/registration.h"
#include "registration/scan_levels.h"
#include "registration/score_constants.h"
#include "support/parallel.h"

namespace ndtom::registration {

struct ObjectiveValue {
  double score = 0;  ///< Σ d1·exp(−d2/2·s) over every term (scan item × nearby map Gaussian)
  Vector6d gradient = Vector6d::Zero();
  Matrix6d hessian = Matrix6d::Zero();
  size_t matched = 0;  ///< scan items with a term at s < 9 (3σ)
  size_t items = 0;    ///< scan items scored

  void add(const ObjectiveValue& other);
};

/// Gauss-Newton information of the terms at s < 9, Σ JᵀΣ⁻¹J, and their Σ s and count.
struct PoseInformation {
  Matrix6d information = Matrix6d::Zero();
  double chi2 = 0;
  size_t terms = 0;

  void add(const PoseInformation& other);
};

class NdtObjective {
 public:
  NdtObjective(const GaussianLookup& map, const ScanLevel& scan, RegistrationMethod method,
               const ScoreConstants& constants, WorkerPool& pool, int threads)
      : map_(map), scan_(scan), method_(method), k_(constants), pool_(pool), threads_(threads) {}

  ObjectiveValue evaluate(const Eigen::Isometry3d& pose, bool derivatives) const;
  PoseInformation information(const Eigen::Isometry3d& pose) const;
  /// Whether scan item `i` at `pose` lies within 3σ of a map Gaussian (counted as matched).
  bool matches(const Eigen::Isometry3d& pose, size_t i) const;

 private:
  static constexpr size_t kChunk = 256;  // scan items per partial sum

  template <class Result, class PerItem>
  Result sumOverItems(PerItem&& per_item) const;

  void scorePoint(const Eigen::Isometry3d& pose, size_t i, bool derivatives,
                  ObjectiveValue& out) const;
  void scoreGaussian(const Eigen::Isometry3d& pose, size_t i, bool derivatives,
                     ObjectiveValue& out) const;
  void informationOfItem(const Eigen::Isometry3d& pose, size_t i, PoseInformation& out) const;

  const GaussianLookup& map_;
  const ScanLevel& scan_;
  RegistrationMethod method_;
  ScoreConstants k_;
  WorkerPool& pool_;
  int threads_;
};

}  // namespace ndtom::registration
