// Exact voxel traversal of a segment (Amanatides & Woo, "A Fast Voxel Traversal Algorithm for
// Ray Tracing", Eurographics 1987), in the library's half-open cell convention.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <utility>

#include "ndtom/map/cell_index.h"

namespace ndtom {

/// Parameter t of from + t·(to − from) where the segment crosses the plane x_a = boundary.
/// The traversal and its brute-force test oracle both use this one formula, so they agree
/// bit for bit on which crossing comes first.
inline double crossingTime(double boundary, double from, double inv_delta) {
  return (boundary - from) * inv_delta;
}

/// The traversal, for walkers that follow it step by step. A Walker provides
///   void start(const CellIndex& first);   // the cell of `from`
///   template <int Axis> void move(int32_t step);  // the current cell moved by ±1 on Axis
///   bool visit();                         // visit the current cell; false stops the walk
/// Knowing which axis moved lets a walker keep incremental state (e.g. an offset in a block)
/// instead of recomputing it from the coordinates at every cell.
///
/// The walk visits, in order, every cell that contains a point of the segment [from, to],
/// except the cell of `to` (that one holds the hit, not free space). Both points must satisfy
/// geometry.inRange(). The walker is taken and returned by value, so its state lives in
/// registers during the walk and the caller keeps its final state.
///
/// Cells are half-open, so where the segment passes exactly through an edge or corner, axes
/// moving up enter the next cell at the crossing time t (the boundary belongs to the upper
/// cell) and axes moving down leave only after t. Up-steps therefore happen first, and a cell
/// touched at the single instant t is visited too; simultaneous up-steps (or down-steps) skip
/// the side cells, which the segment never touches.
template <class Walker>
Walker walkRay(const GridGeometry& geometry, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
               Walker walker);

/// walkRay for many rays from one origin in one call: for i in [begin, end), the ray from
/// `from` to *rayEnd(i, walker), skipping rays for which rayEnd returns nullptr (rayEnd may also
/// set up the walker for its ray). The walker stays in registers from ray to ray: passed and
/// returned through memory per ray, it would stall on store forwarding.
template <class Walker, class RayEnd>
Walker walkRays(const GridGeometry& geometry, const Eigen::Vector3d& from, size_t begin, size_t end,
                RayEnd&& rayEnd, Walker walker);

/// Calls visit(cell) for every cell walkRay visits, in order; visit returns false to stop.
/// The visitor is taken and returned by value, like the walker.
template <class Visit>
Visit traverseRay(const GridGeometry& geometry, const Eigen::Vector3d& from,
                  const Eigen::Vector3d& to, Visit visit);

// --- Implementation --------------------------------------------------------------------

namespace detail {

template <int Axis, class Walker>
void moveAxis(Walker& w, int32_t step) {
  w.template move<Axis>(step);
}

template <class Walker>
void moveRuntimeAxis(Walker& w, int axis, int32_t step) {
  if (axis == 0) moveAxis<0>(w, step);
  if (axis == 1) moveAxis<1>(w, step);
  if (axis == 2) moveAxis<2>(w, step);
}

/// Adapts a visit(cell) callback to the Walker interface.
template <class Visit>
struct CellVisitorWalker {
  Visit visitor;
  CellIndex cell;
  void start(const CellIndex& first) { cell = first; }
  template <int Axis>
  void move(int32_t step) {
    if constexpr (Axis == 0) cell.x += step;
    if constexpr (Axis == 1) cell.y += step;
    if constexpr (Axis == 2) cell.z += step;
  }
  bool visit() { return visitor(static_cast<const CellIndex&>(cell)); }
};

/// walker.start(first), or walker.resume(first) for a walk resumed away from the ray's start
/// if the walker has that (it may keep what it cached for the start).
template <class Walker>
auto startWalker(Walker& w, const CellIndex& first, bool resumed, int)
    -> decltype(w.resume(first), void()) {
  if (resumed)
    w.resume(first);
  else
    w.start(first);
}
template <class Walker>
void startWalker(Walker& w, const CellIndex& first, bool, long) {
  w.start(first);
}

/// What the walk of [from, to] computes once per ray, whichever cell it starts from (a
/// distributed build resumes one ray's walk several times).
struct RaySteps {
  CellIndex last;  ///< the cell of `to`
  int32_t step[3], up[3];
  double inv[3];  ///< 1 / (to - from) per axis, 0 where the ray does not move

  RaySteps(const GridGeometry& geometry, const Eigen::Vector3d& from, const Eigen::Vector3d& to)
      : RaySteps(from, to, geometry.cellOf(to)) {}
  /// With the cell of `to` already known.
  RaySteps(const Eigen::Vector3d& from, const Eigen::Vector3d& to, const CellIndex& last_cell)
      : last(last_cell) {
    for (int a = 0; a < 3; ++a) {
      const double delta = to[a] - from[a];
      step[a] = delta > 0 ? 1 : (delta < 0 ? -1 : 0);
      up[a] = delta > 0 ? 1 : 0;
      inv[a] = delta != 0 ? 1.0 / delta : 0.0;
    }
  }
};

/// The walk of [from, to] from `first`, a cell it passes through, to its end or to the last
/// crossing at a time t <= t_end (<= 1), whichever comes first. The walk's next step depends
/// only on its current cell (crossing times come from boundary indices, not accumulated), so
/// a walk resumed at a cell continues exactly as the walk from `from` would. `ray` is
/// RaySteps(geometry, from, to), which a caller resuming one ray several times computes once
/// (same values, so the same walk); a step along one axis alone is taken only at times up to
/// t_single_end (<= t_end: a resumed stretch stops short of the cell past its end, see
/// owned_ray_walk.h); `resumed`: `first` is not the cell of `from`.
template <class Walker>
[[gnu::always_inline]] inline void walkSegmentFrom(const GridGeometry& geometry,
                                                   const Eigen::Vector3d& from,
                                                   const RaySteps& ray,
                                                   const CellIndex& first, double t_end,
                                                   double t_single_end, bool resumed,
                                                   Walker& walker) {
  const CellIndex last = ray.last;
  if (first == last) return;
  startWalker(walker, first, resumed, 0);

  // Local scalars whose address never escapes, so the compiler keeps them in registers.
  constexpr double kNever = std::numeric_limits<double>::infinity();
  int32_t cell[3] = {first.x, first.y, first.z};
  int32_t step[3], up[3];
  double inv[3], t_next[3];
  for (int a = 0; a < 3; ++a) {
    step[a] = ray.step[a], up[a] = ray.up[a], inv[a] = ray.inv[a];
    t_next[a] =
        step[a] != 0 ? crossingTime(geometry.cellMin(cell[a] + up[a]), from[a], inv[a]) : kNever;
  }
  // Index of the next boundary on each axis, kept as a double: integers are exact there, and
  // the crossing time needs it as a double anyway (one conversion less per step).
  double bx = cell[0] + up[0], by = cell[1] + up[1], bz = cell[2] + up[2];
  double tx = t_next[0], ty = t_next[1], tz = t_next[2];
  const int32_t sx = step[0], sy = step[1], sz = step[2];
  const double dx = sx, dy = sy, dz = sz;
  const double ix = inv[0], iy = inv[1], iz = inv[2];
  const double fx = from[0], fy = from[1], fz = from[2];
  const int32_t lx = last.x, ly = last.y, lz = last.z;
  const double r = geometry.resolution();

  // Each step moves one axis one cell towards `last`, so the walk ends after exactly this
  // many steps; counting them is cheaper than comparing the cell with `last` every time.
  auto stepsLeft = [&] {
    return int64_t(std::abs(int64_t(lx) - cell[0])) + std::abs(int64_t(ly) - cell[1]) +
           std::abs(int64_t(lz) - cell[2]);
  };
  int64_t remaining = stepsLeft();

  for (;;) {
    if (!walker.visit()) return;
    // Branches, not a branch-free choice of the axis: the branch predicts well
    // (doc/benchmarks.md). Each branch guards against rounding taking the walk past the end
    // of the segment.
    if (tx < ty && tx < tz) {
      if (!(tx <= t_single_end)) return;
      bx += dx;
      walker.template move<0>(sx);
      tx = crossingTime(bx * r, fx, ix);
    } else if (ty < tx && ty < tz) {
      if (!(ty <= t_single_end)) return;
      by += dy;
      walker.template move<1>(sy);
      ty = crossingTime(by * r, fy, iy);
    } else if (tz < tx && tz < ty) {
      if (!(tz <= t_single_end)) return;
      bz += dz;
      walker.template move<2>(sz);
      tz = crossingTime(bz * r, fz, iz);
    } else {  // through an edge or a corner: up-steps first, then the down-steps
      const double t = std::min(tx, std::min(ty, tz));
      if (!(t <= t_end)) return;
      cell[0] = int32_t(bx) - up[0], cell[1] = int32_t(by) - up[1], cell[2] = int32_t(bz) - up[2];
      t_next[0] = tx, t_next[1] = ty, t_next[2] = tz;
      bool crossing[3], moved_up = false, down_pending = false;
      for (int a = 0; a < 3; ++a) {
        crossing[a] = t_next[a] == t;
        if (!crossing[a]) continue;
        if (step[a] < 0) {
          down_pending = true;
          continue;
        }
        cell[a] += 1;
        detail::moveRuntimeAxis(walker, a, 1);
        t_next[a] = crossingTime(geometry.cellMin(cell[a] + 1), from[a], inv[a]);
        moved_up = true;
      }
      if (moved_up && down_pending) {  // the cell holding p(t) itself
        if (cell[0] == lx && cell[1] == ly && cell[2] == lz) return;
        if (!walker.visit()) return;
      }
      for (int a = 0; a < 3; ++a) {
        if (!crossing[a] || step[a] >= 0) continue;
        cell[a] -= 1;
        detail::moveRuntimeAxis(walker, a, -1);
        t_next[a] = crossingTime(geometry.cellMin(cell[a]), from[a], inv[a]);
      }
      bx = cell[0] + up[0], by = cell[1] + up[1], bz = cell[2] + up[2];
      tx = t_next[0], ty = t_next[1], tz = t_next[2];
      remaining = stepsLeft() + 1;  // the decrement below applies to the single steps only
    }
    if (--remaining <= 0) return;
  }
}

/// walkSegmentFrom for a walk computing the ray's RaySteps itself.
template <class Walker>
[[gnu::always_inline]] inline void walkSegmentFrom(const GridGeometry& geometry,
                                                   const Eigen::Vector3d& from,
                                                   const Eigen::Vector3d& to, const CellIndex& first,
                                                   double t_end, Walker& walker) {
  walkSegmentFrom(geometry, from, RaySteps(geometry, from, to), first, t_end, t_end, false,
                  walker);
}

template <class Walker>
[[gnu::always_inline]] inline void walkSegment(const GridGeometry& geometry,
                                               const Eigen::Vector3d& from,
                                               const Eigen::Vector3d& to, Walker& walker) {
  walkSegmentFrom(geometry, from, to, geometry.cellOf(from), 1.0, walker);
}

}  // namespace detail

template <class Walker>
Walker walkRay(const GridGeometry& geometry, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
               Walker walker) {
  // A by-value parameter lives in memory, and so would a named return value; a local that is
  // neither can live in registers.
  Walker local(std::move(walker));
  detail::walkSegment(geometry, from, to, local);
  return Walker(std::move(local));
}

template <class Walker, class RayEnd>
Walker walkRays(const GridGeometry& geometry, const Eigen::Vector3d& from, size_t begin, size_t end,
                RayEnd&& rayEnd, Walker walker) {
  Walker local(std::move(walker));
  for (size_t i = begin; i < end; ++i)
    if (const Eigen::Vector3d* to = rayEnd(i, local))
      detail::walkSegment(geometry, from, *to, local);
  return Walker(std::move(local));
}

template <class Visit>
Visit traverseRay(const GridGeometry& geometry, const Eigen::Vector3d& from,
                  const Eigen::Vector3d& to, Visit visit) {
  return walkRay(geometry, from, to, detail::CellVisitorWalker<Visit>{std::move(visit), {}})
      .visitor;
}

}  // namespace ndtom
