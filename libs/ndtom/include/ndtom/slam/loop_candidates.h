// Which older keyframes a new one may close a loop with: those the pose graph places within
// the search radius, which grows with the path driven since the last closure (odometry's
// drift), and which are far enough back along the path not to be odometry's own neighbours.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace ndtom {

struct LoopSearchOptions {
  /// Keyframes nearer than this along the path (m) are odometry's neighbours, never a loop
  /// (Default: 60 m).
  double min_path_gap = 60;
  /// Search radius (m): `base_radius` plus `drift_per_metre` times the path since the last
  /// closure (3σ of odometry's drift; Default: 2 m + 1 %) ...
  double base_radius = 2;
  double drift_per_metre = 0.01;
  /// ... at most this (Default: 30 m). Past `max_local_radius` (Default: 6 m) the old
  /// submap is searched whole (global search) instead of around the guess.
  double max_radius = 30;
  double max_local_radius = 6;
  /// Nearest candidates tried per keyframe (Default: 2).
  size_t max_candidates = 2;
};

/// Throws std::invalid_argument("<option> = <value>: <why>") on the first bad value.
void validate(const LoopSearchOptions& options);

/// The search radius after `path_since_closure` metres without a loop closure.
double loopSearchRadius(const LoopSearchOptions& options, double path_since_closure);

struct KeyframePlace {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< as the pose graph has it now
  double path_length = 0;                              ///< odometry path to it (m)
};

/// Indices of the keyframes that `current` may close a loop with, nearest first: within
/// `radius` of it in x and y, at least `min_path_gap` behind it along the path.
std::vector<size_t> loopCandidates(const LoopSearchOptions& options,
                                   const std::vector<KeyframePlace>& keyframes, size_t current,
                                   double radius);

}  // namespace ndtom
