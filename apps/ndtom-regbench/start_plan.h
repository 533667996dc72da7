// The initial guesses every system starts from: per held-out scan, error level and trial, the
// reference pose moved horizontally by the level's distance in a random direction and turned
// about the vertical axis by the level's angle with a random sign. Fixed seeds, so every
// system (and every run with the same seed) gets the same starts.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace ndtom::regbench {

/// An initial error: translation (m) and rotation (degrees).
struct ErrorLevel {
  double meters = 0;
  double degrees = 0;

  std::string label() const;  ///< "1 m / 10°"
};

/// 0.25 m/2.5°, 0.5/5, 1/10, 1.5/15, 2/20, 3/30, 5/45.
std::vector<ErrorLevel> defaultErrorLevels();

struct Start {
  int scan = 0;      ///< number of the held-out scan (fullN.pcd)
  size_t level = 0;  ///< index into the error levels
  int trial = 0;
  Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();  ///< sensor -> world
};

/// `truth` (sensor -> world) moved by `level.meters` along the horizontal direction at
/// `heading` (rad from +x) and turned by `sign`·`level.degrees` about the world's z axis
/// through the sensor.
Eigen::Isometry3d perturbedPose(const Eigen::Isometry3d& truth, const ErrorLevel& level,
                                double heading, int sign);

/// Scan by scan, level by level, trial by trial. Each start's random numbers come from
/// (seed, scan, level's values, trial) alone: the same start whatever else is planned.
std::vector<Start> planStarts(const std::vector<int>& scans,
                              const std::vector<Eigen::Isometry3d>& poses,
                              const std::vector<ErrorLevel>& levels, int trials, uint32_t seed);

}  // namespace ndtom::regbench
