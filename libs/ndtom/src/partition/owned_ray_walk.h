// A ray's walk (ray_dda.h) through only the tiles one process of a distributed build owns
// (tile_ownership.h): the stretches of the ray in other processes' tiles are jumped over, not
// walked, so that N processes share a scan's ray walking instead of each doing all of it.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "map/ray_dda.h"
#include "ndtom/partition/tile_ownership.h"
#include "partition/tile_owner_table.h"

namespace ndtom {

/// Walks rays through the owned tiles (no state: a class for its private helpers). Hidden:
/// its out-of-line helpers are called directly, not through a shared library's PLT.
class [[gnu::visibility("hidden")]] OwnedRayWalk {
  static constexpr int kMaxStretchesPerRay = 16;

 public:
  /// Visits, in order, the cells of walkRay(from, to) that lie in tiles `owned` owns, with
  /// walkRay's walker interface, and a few more: each stretch of owned tiles is walked from
  /// the cell before it to the cells after it (in other processes' tiles), which the caller
  /// must ignore. Over all processes, each cell of walkRay(from, to) is visited exactly once
  /// in an owned tile.
  template <class Walker>
  static void walk(const GridGeometry& geometry, const Eigen::Vector3d& from,
                   const Eigen::Vector3d& to, const TileOwnerTable& owned, Walker& walker);

  /// walk() for many rays from one origin, as walkRays() in ray_dda.h: for i in [begin, end),
  /// the ray to *rayEnd(i, walker), skipping nullptr. The walker stays in registers from ray
  /// to ray, and the origin's cell and tile are found once.
  template <class Walker, class RayEnd>
  static Walker walkRays(const GridGeometry& geometry, const Eigen::Vector3d& from, size_t begin,
                         size_t end, const TileOwnerTable& owned, RayEnd&& rayEnd, Walker walker);

 private:
  /// What every ray from one origin shares.
  struct Origin {
    CellIndex cell, tile;
    TileOwnerTable::Lookup owner;  ///< a copy, kept in registers
    int64_t index;             ///< its tile's in the table of owners, -1 if none
    bool owned;                ///< its tile
  };
  static Origin originOf(const GridGeometry& geometry, const Eigen::Vector3d& from,
                         const TileOwnerTable& owned) {
    const CellIndex cell = geometry.cellOf(from), tile = owned.tileOf(cell);
    const TileOwnerTable::Lookup owner = owned.lookup();
    return {cell, tile, owner, owner.indexOf(tile), owned.ownsTile(tile)};
  }
  template <class Walker>
  [[gnu::always_inline]] static inline void walkOne(const GridGeometry& geometry,
                                                    const Eigen::Vector3d& from,
                                                    const Origin& origin, const Eigen::Vector3d& to,
                                                    Walker& walker);

  struct Stretch {       // of consecutive owned tiles
    double t_in, t_out;  ///< entered at t_in (-inf: at the start), left at t_out (+inf: never)
    CellIndex resume;    ///< the walk's cell after every crossing before t_in
  };
  /// A ray's stretches, in order; one that starts under kJoinCells after the one before joins
  /// it, so each crossing time belongs to one stretch at most and no cell is visited twice.
  struct Stretches {
    Stretches(const GridGeometry& g, const Eigen::Vector3d& f, const Eigen::Vector3d& t,
              const detail::RaySteps& steps, const CellIndex& first_cell)
        : geometry(g), from(f), to(t), ray(steps), first(first_cell) {}  // list left unset
    const GridGeometry& geometry;
    const Eigen::Vector3d &from, &to;
    const detail::RaySteps& ray;
    const CellIndex& first;
    Stretch list[kMaxStretchesPerRay];
    int n = 0;
    double cells = -1;  ///< the walk's steps, once needed

    void enter(double t_in);
    void leave(double t_out) { list[n - 1].t_out = t_out; }
  };

  /// The owner of the walk's current tile at the scale of tiles, as an index in the table of
  /// owners that follows the walk's steps (every tile the walk enters is in the table).
  struct TableSteps {
    const uint8_t* owned;
    int64_t index;
    int64_t delta[3];  ///< the index's change per step on each axis
    void step(int axis) { index += delta[axis]; }
    bool owns() const { return owned[index] != 0; }
  };
  /// The same by the tile's coordinates, for tiles the table may not hold.
  struct LookupSteps {
    const TileOwnerTable::Lookup& lookup;
    CellIndex tile;
    const int32_t* delta;  ///< the ray's steps
    void step(int axis) { tile[axis] += delta[axis]; }
    bool owns() const { return lookup.ownsTile(tile); }
  };
  /// The walk at the scale of tiles from the origin's tile (`here`: owned), into `out`.
  template <class Owner>
  [[gnu::always_inline]] static inline void findStretches(const Eigen::Vector3d& from,
                                                          int32_t edge, const CellIndex& tile,
                                                          bool here, Owner owner, Stretches& out);

  /// The cell after the resume cell if the walk enters the stretch by one step there, else
  /// the resume cell.
  static CellIndex firstOwnedCell(const GridGeometry& geometry, const Eigen::Vector3d& from,
                                  const detail::RaySteps& ray, const Stretch& s);
  static constexpr int kJoinCells = 8;
};

// --- Implementation --------------------------------------------------------------------

namespace detail {

/// The largest double below t, for crossing times (t >= 0): std::nextafter without the call.
inline double justBelow(double t) {
  if (t == 0) return -std::numeric_limits<double>::denorm_min();
  uint64_t bits;
  std::memcpy(&bits, &t, sizeof bits);
  --bits;
  std::memcpy(&t, &bits, sizeof bits);
  return t;
}

/// The walk's cell once every crossing earlier than t is done (a cell it passes through, as
/// crossings happen in time order). Each axis moves on its own: it has crossed exactly the
/// boundaries whose crossing time, by the walk's own formula, is below t. False if an axis
/// went past `ray.last` by then (a ray end within rounding of a boundary): the walk from
/// there would not match its remaining-step count (`out` is then left as it was). `ray` must
/// be RaySteps(geometry, from, to).
inline bool cellBefore(const GridGeometry& geometry, const Eigen::Vector3d& from,
                       const Eigen::Vector3d& to, const RaySteps& ray, const CellIndex& first,
                       double t, CellIndex& out) {
  const double r = geometry.resolution(), inv_r = geometry.invResolution();
  const CellIndex& last = ray.last;
  CellIndex cell;
  for (int a = 0; a < 3; ++a) {
    int32_t c = first[a];
    if (ray.step[a] != 0) {
      const double inv = ray.inv[a];
      // Near the answer (only a start: corrected below, so a product is as good as the
      // division); cast and adjust: std::floor is a call on baseline x86-64.
      const double scaled = (from[a] + t * (to[a] - from[a])) * inv_r;
      const double guess = double(int32_t(scaled) - (scaled < double(int32_t(scaled))));
      auto crossing = [&](int32_t boundary) { return crossingTime(double(boundary) * r, from[a], inv); };
      if (ray.step[a] > 0) {  // leaves cell c at boundary c + 1
        c = int32_t(std::clamp(guess, double(first[a]), double(last[a])));
        while (c > first[a] && crossing(c) >= t) --c;
        while (crossing(c + 1) < t) ++c;
        if (c > last[a]) return false;
      } else {  // leaves cell c at boundary c
        c = int32_t(std::clamp(guess, double(last[a]), double(first[a])));
        while (c < first[a] && crossing(c + 1) >= t) ++c;
        while (crossing(c) < t) --c;
        if (c < last[a]) return false;
      }
    }
    cell[a] = c;
  }
  out = cell;  // only a whole cell: a caller falling back keeps its own
  return true;
}

}  // namespace detail

template <class Walker>
void OwnedRayWalk::walk(const GridGeometry& geometry, const Eigen::Vector3d& from,
                        const Eigen::Vector3d& to, const TileOwnerTable& owned, Walker& walker) {
  Walker local(std::move(walker));
  walkOne(geometry, from, originOf(geometry, from, owned), to, local);
  walker = std::move(local);
}

template <class Walker, class RayEnd>
Walker OwnedRayWalk::walkRays(const GridGeometry& geometry, const Eigen::Vector3d& from,
                              size_t begin, size_t end, const TileOwnerTable& owned,
                              RayEnd&& rayEnd, Walker walker) {
  const Origin origin = originOf(geometry, from, owned);
  Walker local(std::move(walker));
  for (size_t i = begin; i < end; ++i)
    if (const Eigen::Vector3d* to = rayEnd(i, local))
      walkOne(geometry, from, origin, *to, local);
  return Walker(std::move(local));
}

template <class Walker>
inline void OwnedRayWalk::walkOne(const GridGeometry& geometry, const Eigen::Vector3d& from,
                                  const Origin& origin, const Eigen::Vector3d& to,
                                  Walker& walker) {
  const CellIndex& first = origin.cell;
  const CellIndex last = geometry.cellOf(to);
  if (first == last) return;
  const TileOwnerTable::Lookup& owner = origin.owner;
  const int32_t edge = owner.edge;
  const CellIndex end_tile{owner.tileOf(last.x), owner.tileOf(last.y), owner.tileOf(last.z)};

  // Most rays end in the tile they start in: then no crossing time is needed, unless the
  // ray's end cell lies on the face of the tile it moves towards (where rounding may let the
  // walk step one cell past it).
  auto staysIn = [edge](int32_t end, int32_t end_tile_a, int32_t tile_a, double delta) {
    const int32_t offset = end - end_tile_a * edge;
    return end_tile_a == tile_a && !(delta > 0 && offset == edge - 1) &&
           !(delta < 0 && offset == 0);
  };
  if (staysIn(last.x, end_tile.x, origin.tile.x, to.x() - from.x()) &&
      staysIn(last.y, end_tile.y, origin.tile.y, to.y() - from.y()) &&
      staysIn(last.z, end_tile.z, origin.tile.z, to.z() - from.z())) {
    if (origin.owned)
      detail::walkSegmentFrom(geometry, from, detail::RaySteps(from, to, last), first, 1.0, 1.0,
                              false, walker);
    return;
  }
  const detail::RaySteps ray(from, to, last);  // once for the tiles and every stretch

  // The walk enters only tiles between the origin's and one past the end's (rounding), so if
  // that one is in the table, so are all.
  Stretches stretches{geometry, from, to, ray, first};
  if (origin.index >= 0 && owner.holdsAround(end_tile)) {
    const int64_t nx = int64_t(owner.nx), nxy = nx * int64_t(owner.ny);
    findStretches(from, edge, origin.tile, origin.owned,
                  TableSteps{owner.owned, origin.index,
                             {ray.step[0], ray.step[1] * nx, ray.step[2] * nxy}},
                  stretches);
  } else {
    findStretches(from, edge, origin.tile, origin.owned,
                  LookupSteps{owner, origin.tile, ray.step}, stretches);
  }

  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (int k = 0; k < stretches.n; ++k) {
    const Stretch& s = stretches.list[k];
    if (s.resume == last) break;  // the walk ended before this stretch
    // The stretch's own cells only, where that is the walk's: a step along one axis alone at
    // t_in enters it (the cell before is another process's), and one at t_out leaves it (the
    // tile axis alone crosses then, into another process's tile). Ties keep the cells around
    // them, as the walk's corner rule decides what is touched there.
    const CellIndex start = s.t_in == -kInf ? s.resume : firstOwnedCell(geometry, from, ray, s);
    const bool ends = s.t_out <= 1.0;
    detail::walkSegmentFrom(geometry, from, ray, start, ends ? s.t_out : 1.0,
                            ends ? detail::justBelow(s.t_out) : 1.0, s.t_in != -kInf, walker);
  }
}

inline void OwnedRayWalk::Stretches::enter(double t_in) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // A resume costs about as much as walking kJoinCells cells: shorter gaps of other tiles
  // (and a short start from the sensor) are walked through, their counts dropped later like
  // the stretch ends'. The owned cells are visited once either way. A span of time times the
  // walk's steps is about the cells it walks then.
  if (cells < 0)
    cells = double(std::abs(int64_t(ray.last.x) - first.x) +
                   std::abs(int64_t(ray.last.y) - first.y) +
                   std::abs(int64_t(ray.last.z) - first.z));
  if (n > 0 && ((t_in - list[n - 1].t_out) * cells < kJoinCells || n == kMaxStretchesPerRay)) {
    list[n - 1].t_out = kInf;  // (a ray crossing that many tiles: walked through)
    return;
  }
  Stretch s{t_in, kInf, first};
  // Resumed in the tile before it, not owned. A ray end within rounding of a boundary may
  // leave no cell to resume at: then the walk goes on from the stretch before, or the start.
  if (n == 0 && t_in * cells < kJoinCells) {
    s.t_in = -kInf;
  } else if (!detail::cellBefore(geometry, from, to, ray, first, t_in, s.resume)) {
    if (n > 0) {
      list[n - 1].t_out = kInf;
      return;
    }
    s = {-kInf, kInf, first};
  }
  list[n++] = s;
}

// The same crossing times as the cell walk's (computed from the same boundary indices, held as
// doubles: integers are exact there), the same order (at equal times up-steps first).
template <class Owner>
void OwnedRayWalk::findStretches(const Eigen::Vector3d& from, int32_t edge, const CellIndex& tile,
                                 bool here, Owner owner, Stretches& out) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const detail::RaySteps& ray = out.ray;
  const double r = out.geometry.resolution();
  // Scalars for the loop, whose addresses never escape.
  const double fx = from.x(), fy = from.y(), fz = from.z();
  const double ix = ray.inv[0], iy = ray.inv[1], iz = ray.inv[2];
  const double mx = double(ray.step[0] * edge), my = double(ray.step[1] * edge),
               mz = double(ray.step[2] * edge);
  double bx = double(int64_t(tile.x + ray.up[0]) * edge),
         by = double(int64_t(tile.y + ray.up[1]) * edge),
         bz = double(int64_t(tile.z + ray.up[2]) * edge);
  double tx = ray.step[0] != 0 ? crossingTime(bx * r, fx, ix) : kInf;
  double ty = ray.step[1] != 0 ? crossingTime(by * r, fy, iy) : kInf;
  double tz = ray.step[2] != 0 ? crossingTime(bz * r, fz, iz) : kInf;

  if (here) out.list[out.n++] = {-kInf, kInf, out.first};
  for (;;) {
    double t;
    bool owned_on_the_way = false;
    const bool was_here = here;
    if (tx < ty && tx < tz) {  // one axis crosses: one tile on
      t = tx;
      if (!(t <= 1.0)) break;
      bx += mx;
      tx = crossingTime(bx * r, fx, ix);
      owner.step(0);
      here = owner.owns();
    } else if (ty < tx && ty < tz) {
      t = ty;
      if (!(t <= 1.0)) break;
      by += my;
      ty = crossingTime(by * r, fy, iy);
      owner.step(1);
      here = owner.owns();
    } else if (tz < tx && tz < ty) {
      t = tz;
      if (!(t <= 1.0)) break;
      bz += mz;
      tz = crossingTime(bz * r, fz, iz);
      owner.step(2);
      here = owner.owns();
    } else {  // an edge or a corner: up-steps first, then down-steps
      t = std::min(tx, std::min(ty, tz));
      if (!(t <= 1.0)) break;
      double b[3] = {bx, by, bz}, tn[3] = {tx, ty, tz};
      const double moves[3] = {mx, my, mz};
      bool moved = false;
      for (const int direction : {1, -1}) {
        bool moved_now = false;
        for (int a = 0; a < 3; ++a) {
          if (tn[a] != t || ray.step[a] != direction) continue;
          owner.step(a);
          b[a] += moves[a];
          tn[a] = crossingTime(b[a] * r, from[a], ray.inv[a]);
          moved_now = true;
        }
        if (moved_now && moved) owned_on_the_way = here;  // the tile between up- and down-steps
        if (moved_now) here = owner.owns(), moved = true;
      }
      bx = b[0], by = b[1], bz = b[2];
      tx = tn[0], ty = tn[1], tz = tn[2];
    }
    if (was_here && !here) {
      out.leave(t);
    } else if (!was_here && here) {
      out.enter(t);
    } else if (!was_here && owned_on_the_way) {  // an owned tile touched at one instant
      out.enter(t);
      out.leave(t);
    }
  }
}

inline CellIndex OwnedRayWalk::firstOwnedCell(const GridGeometry& geometry,
                                              const Eigen::Vector3d& from,
                                              const detail::RaySteps& ray, const Stretch& s) {
  // The walk's next crossing times from the resume cell, as the walk computes them.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double t[3];
  for (int a = 0; a < 3; ++a)
    t[a] = ray.step[a] != 0
               ? crossingTime(geometry.cellMin(s.resume[a] + ray.up[a]), from[a], ray.inv[a])
               : kInf;
  const int a = t[0] < t[1] ? (t[0] < t[2] ? 0 : 2) : (t[1] < t[2] ? 1 : 2);
  const bool alone = t[a] < t[(a + 1) % 3] && t[a] < t[(a + 2) % 3];
  // Moving towards the end cell on that axis, so the step count from there is the walk's.
  if (!alone || !(t[a] == s.t_in) || !(t[a] < s.t_out)) return s.resume;
  if (s.resume[a] == ray.last[a]) return s.resume;
  CellIndex c = s.resume;
  c[a] += ray.step[a];
  return c;
}

}  // namespace ndtom
