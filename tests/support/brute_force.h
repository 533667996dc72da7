// Brute-force oracles shared by the tests: independent of the code under test.
#pragma once

#include <Eigen/Core>
#include <set>

#include "map/ray_dda.h"
#include "ndtom/map/cell_index.h"

namespace ndtom::testing {

using Eigen::Vector3d;

// Does the segment from + t·(to − from), t ∈ [0, 1], meet the half-open box of `cell`?
// Per axis the box is an interval of t, open or closed at each end; intersect them all.
inline bool segmentMeetsCell(const GridGeometry& g, const Vector3d& from, const Vector3d& to,
                             const CellIndex& cell) {
  double t_lo = 0, t_hi = 1;
  bool lo_closed = true, hi_closed = true;
  auto raise_lo = [&](double t, bool closed) {
    if (t > t_lo) {
      t_lo = t;
      lo_closed = closed;
    } else if (t == t_lo) {
      lo_closed = lo_closed && closed;
    }
  };
  auto lower_hi = [&](double t, bool closed) {
    if (t < t_hi) {
      t_hi = t;
      hi_closed = closed;
    } else if (t == t_hi) {
      hi_closed = hi_closed && closed;
    }
  };
  for (int a = 0; a < 3; ++a) {
    const double lo = g.cellMin(cell[a]), hi = g.cellMin(cell[a] + 1);
    const double delta = to[a] - from[a];
    if (delta == 0) {
      if (!(lo <= from[a] && from[a] < hi)) return false;
      continue;
    }
    const double inv = 1.0 / delta;
    const double t_at_lo = ndtom::crossingTime(lo, from[a], inv);
    const double t_at_hi = ndtom::crossingTime(hi, from[a], inv);
    if (delta > 0) {  // inside for t in [t_at_lo, t_at_hi)
      raise_lo(t_at_lo, true);
      lower_hi(t_at_hi, false);
    } else {  // inside for t in (t_at_hi, t_at_lo]
      raise_lo(t_at_hi, false);
      lower_hi(t_at_lo, true);
    }
  }
  return t_lo < t_hi || (t_lo == t_hi && lo_closed && hi_closed);
}

/// Every cell the segment [from, to] meets, except the cell of `to`.
inline std::set<CellIndex> bruteForce(const GridGeometry& g, const Vector3d& from,
                                      const Vector3d& to) {
  const CellIndex a = g.cellOf(from), b = g.cellOf(to);
  std::set<CellIndex> cells;
  for (int32_t x = std::min(a.x, b.x) - 1; x <= std::max(a.x, b.x) + 1; ++x)
    for (int32_t y = std::min(a.y, b.y) - 1; y <= std::max(a.y, b.y) + 1; ++y)
      for (int32_t z = std::min(a.z, b.z) - 1; z <= std::max(a.z, b.z) + 1; ++z) {
        const CellIndex c{x, y, z};
        if (c != b && segmentMeetsCell(g, from, to, c)) cells.insert(c);
      }
  return cells;
}

}  // namespace ndtom::testing
