#include "start_plan.h"

#include <cmath>
#include <cstdio>
#include <random>

namespace ndtom::regbench {

std::string ErrorLevel::label() const {
  char text[64];
  std::snprintf(text, sizeof text, "%g m / %g°", meters, degrees);
  return text;
}

std::vector<ErrorLevel> defaultErrorLevels() {
  return {{0.25, 2.5}, {0.5, 5}, {1, 10}, {1.5, 15}, {2, 20}, {3, 30}, {5, 45}};
}

Eigen::Isometry3d perturbedPose(const Eigen::Isometry3d& truth, const ErrorLevel& level,
                                double heading, int sign) {
  Eigen::Isometry3d guess = truth;
  guess.translation() += level.meters * Eigen::Vector3d(std::cos(heading), std::sin(heading), 0);
  const double angle = sign * level.degrees * M_PI / 180;
  guess.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()) * truth.linear();
  return guess;
}

std::vector<Start> planStarts(const std::vector<int>& scans,
                              const std::vector<Eigen::Isometry3d>& poses,
                              const std::vector<ErrorLevel>& levels, int trials, uint32_t seed) {
  std::vector<Start> starts;
  for (int scan : scans)
    for (size_t l = 0; l < levels.size(); ++l)
      for (int trial = 0; trial < trials; ++trial) {
        // seed_seq and mt19937 are fully specified by the standard (the distributions are
        // not): the raw 32-bit outputs give the same starts with any standard library.
        const auto mm = uint32_t(std::llround(levels[l].meters * 1000));
        const auto mdeg = uint32_t(std::llround(levels[l].degrees * 1000));
        std::seed_seq seq{seed, uint32_t(scan), mm, mdeg, uint32_t(trial)};
        std::mt19937 random(seq);
        const double heading = 2 * M_PI * (double(random()) / 4294967296.0);
        const int sign = (random() & 1u) ? 1 : -1;
        starts.push_back(
            {scan, l, trial, perturbedPose(poses.at(size_t(scan)), levels[l], heading, sign)});
      }
  return starts;
}

}  // namespace ndtom::regbench
