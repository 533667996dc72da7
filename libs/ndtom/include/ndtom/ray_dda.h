// Exact voxel traversal of a segment (Amanatides & Woo, "A Fast Voxel Traversal Algorithm for
// Ray Tracing", Eurographics 1987), in the library's half-open cell convention.
#pragma once

#include <Eigen/Core>
#include <limits>

#include "ndtom/cell_index.h"

namespace ndtom {

/// Parameter t of from + t·(to − from) where the segment crosses the plane x_a = boundary.
/// The traversal and its brute-force test oracle both use this one formula, so they agree
/// bit for bit on which crossing comes first.
inline double crossingTime(double boundary, double from, double inv_delta) {
  return (boundary - from) * inv_delta;
}

/// Calls visit(cell) in order for every cell that contains a point of the segment
/// [from, to], except the cell of `to` (that one holds the hit, not free space).
/// visit returns false to stop early. Both points must satisfy geometry.inRange().
///
/// Cells are half-open, so where the segment passes exactly through an edge or corner:
/// axes moving up enter the next cell at the crossing time t (the boundary belongs to the
/// upper cell), axes moving down leave only after t. Up-steps therefore happen first, and a
/// cell touched at the single instant t is visited too; simultaneous up-steps (or down-steps)
/// skip the side cells, which the segment never touches.
template <class Visit>
void traverseRay(const GridGeometry& geometry, const Eigen::Vector3d& from,
                 const Eigen::Vector3d& to, Visit&& visit) {
  CellIndex cell = geometry.cellOf(from);
  const CellIndex last = geometry.cellOf(to);
  if (cell == last) return;

  constexpr double kNever = std::numeric_limits<double>::infinity();
  int step[3];
  double inv_delta[3], t_next[3];
  for (int a = 0; a < 3; ++a) {
    const double delta = to[a] - from[a];
    if (delta > 0) {
      step[a] = 1;
      inv_delta[a] = 1.0 / delta;
      t_next[a] = crossingTime(geometry.cellMin(cell[a] + 1), from[a], inv_delta[a]);
    } else if (delta < 0) {
      step[a] = -1;
      inv_delta[a] = 1.0 / delta;
      t_next[a] = crossingTime(geometry.cellMin(cell[a]), from[a], inv_delta[a]);
    } else {
      step[a] = 0;
      inv_delta[a] = 0;
      t_next[a] = kNever;
    }
  }
  auto advance = [&](int a) {
    cell[a] += step[a];
    const int32_t boundary_cell = step[a] > 0 ? cell[a] + 1 : cell[a];
    t_next[a] = crossingTime(geometry.cellMin(boundary_cell), from[a], inv_delta[a]);
  };

  for (;;) {
    if (!visit(static_cast<const CellIndex&>(cell))) return;
    const int a =
        t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
    const double t = t_next[a];
    if (!(t <= 1.0)) return;  // rounding guard: the segment ends in this cell
    const bool tie = (t_next[(a + 1) % 3] == t) || (t_next[(a + 2) % 3] == t);
    if (!tie) {
      advance(a);
    } else {
      bool crossing[3], moved_up = false, down_pending = false;
      for (int b = 0; b < 3; ++b) crossing[b] = t_next[b] == t;
      for (int b = 0; b < 3; ++b) {
        if (!crossing[b]) continue;
        if (step[b] > 0) {
          advance(b);
          moved_up = true;
        } else {
          down_pending = true;
        }
      }
      if (down_pending) {
        if (moved_up) {  // the cell holding p(t) itself
          if (cell == last) return;
          if (!visit(static_cast<const CellIndex&>(cell))) return;
        }
        for (int b = 0; b < 3; ++b)
          if (crossing[b] && step[b] < 0) advance(b);
      }
    }
    if (cell == last) return;
  }
}

}  // namespace ndtom
