// What one scan insertion did: every input point is accounted for exactly once.
#pragma once

#include <cstddef>
#include <string>

namespace ndtom {

/// Longest ray traced, in cells (6.5 km at 0.1 m). A farther point is rejected rather than
/// traced: a glitch at 1e8 m would otherwise take minutes and gigabytes. Set max_range to
/// truncate long rays instead.
inline constexpr double kMaxRayCells = 65536;

struct InsertionReport {
  size_t points_in = 0;             ///< points given
  size_t hits = 0;                  ///< points counted in N_p of their cell (Eq. 12) and merged
  size_t truncated = 0;             ///< beyond max_range: a free ray up to max_range, no hit
  size_t rejected_non_finite = 0;   ///< NaN or Inf coordinates
  size_t rejected_too_close = 0;    ///< closer than min_range, or at the sensor origin
  size_t rejected_out_of_grid = 0;  ///< outside the supported coordinate range (see cell_index.h)
  size_t rejected_too_far = 0;  ///< ray longer than kMaxRayCells cells (a glitch, not a reading)

  size_t cells_touched = 0;     ///< distinct cells whose occupancy was updated
  size_t cells_hit = 0;         ///< cells with N_p > 0
  size_t cells_created = 0;     ///< cells observed for the first time
  size_t gaussians_gained = 0;  ///< cells that now have a Gaussian (N ≥ 3) and had none
  size_t gaussians_lost = 0;    ///< cells whose Gaussian was discarded (log-odds ≤ 0)
  size_t rays_cast = 0;         ///< segments traversed (per point, or per hit cell)
  size_t voxel_visits = 0;      ///< cells visited by the ray traversal

  size_t pointsUsed() const { return hits + truncated; }
  size_t rejected() const {
    return rejected_non_finite + rejected_too_close + rejected_out_of_grid + rejected_too_far;
  }
  InsertionReport& operator+=(const InsertionReport& o);
  std::string toString() const;
};

}  // namespace ndtom
