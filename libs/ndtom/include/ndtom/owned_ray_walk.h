// A ray's walk (ray_dda.h) through only the tiles one process of a distributed build owns
// (tile_ownership.h): the stretches of the ray in other processes' tiles are jumped over, not
// walked, so that N processes share a scan's ray walking instead of each doing all of it.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "ndtom/ray_dda.h"
#include "ndtom/tile_ownership.h"

namespace ndtom {

/// Walks rays through the owned tiles; keeps its buffers from ray to ray (one per thread).
class OwnedRayWalk {
 public:
  /// Visits, in order, the cells of walkRay(from, to) that lie in tiles `owned` owns, with
  /// walkRay's walker interface, and a few more: each stretch of owned tiles is walked from
  /// the cell before it to the cells after it (in other processes' tiles), which the caller
  /// must ignore. Over all processes, each cell of walkRay(from, to) is visited exactly once
  /// in an owned tile.
  template <class Walker>
  void walk(const GridGeometry& geometry, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
            const TileOwnership& owned, Walker& walker);

 private:
  struct Stretch {       // of consecutive owned tiles
    double t_in, t_out;  ///< entered at t_in (-inf: at the start), left at t_out (+inf: never)
    CellIndex resume;    ///< the walk's cell after every crossing before t_in
  };
  bool ownsTile(const TileOwnership& owned, const CellIndex& tile) {
    if (!(tile == cached_tile_) || owned.rank != cached_for_.rank ||  // rays share first tiles
        owned.ranks != cached_for_.ranks || owned.tile_blocks != cached_for_.tile_blocks) {
      cached_tile_ = tile, cached_for_ = owned, cached_owned_ = owned.ownsTile(tile);
    }
    return cached_owned_;
  }
  std::vector<Stretch> stretches_;
  CellIndex cached_tile_;
  TileOwnership cached_for_{1, 0, 0};  // matches no real ownership
  bool cached_owned_ = false;
};

// --- Implementation --------------------------------------------------------------------

namespace detail {

/// The walk's cell once every crossing earlier than t is done (a cell it passes through, as
/// crossings happen in time order). Each axis moves on its own: it has crossed exactly the
/// boundaries whose crossing time, by the walk's own formula, is below t. False if an axis
/// went past `last` by then (a ray end within rounding of a boundary): the walk from there
/// would not match its remaining-step count.
inline bool cellBefore(const GridGeometry& geometry, const Eigen::Vector3d& from,
                       const Eigen::Vector3d& to, const CellIndex& first, const CellIndex& last,
                       double t, CellIndex& out) {
  const double r = geometry.resolution();
  for (int a = 0; a < 3; ++a) {
    const double delta = to[a] - from[a];
    int32_t c = first[a];
    if (delta != 0) {
      const double inv = 1.0 / delta;
      // Near the answer (corrected below); cast and adjust: std::floor is a call on baseline x86-64.
      const double scaled = (from[a] + t * delta) / r;
      const double guess = double(int32_t(scaled) - (scaled < double(int32_t(scaled))));
      auto crossing = [&](int32_t boundary) { return crossingTime(double(boundary) * r, from[a], inv); };
      if (delta > 0) {  // leaves cell c at boundary c + 1
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
    out[a] = c;
  }
  return true;
}

}  // namespace detail

template <class Walker>
void OwnedRayWalk::walk(const GridGeometry& geometry, const Eigen::Vector3d& from,
                        const Eigen::Vector3d& to, const TileOwnership& owned, Walker& walker) {
  const CellIndex first = geometry.cellOf(from), last = geometry.cellOf(to);
  if (first == last) return;
  const int32_t edge = owned.tileCells();
  auto tileOf = [&](int32_t cell) {  // a shift for the usual power-of-two tiles
    return (edge & (edge - 1)) == 0 ? cell >> __builtin_ctz(uint32_t(edge)) : floorDiv(cell, edge);
  };
  CellIndex tile{tileOf(first.x), tileOf(first.y), tileOf(first.z)};

  // Most rays end in the tile they start in: then no crossing time is needed, unless the
  // ray's end cell lies on the face of the tile it moves towards (where rounding may let the
  // walk step one cell past it).
  bool one_tile = true;
  for (int a = 0; a < 3 && one_tile; ++a) {
    const int32_t end = last[a], end_tile = tileOf(end), offset = end - end_tile * edge;
    const double delta = to[a] - from[a];
    one_tile = end_tile == tile[a] && !(delta > 0 && offset == edge - 1) && !(delta < 0 && offset == 0);
  }
  if (one_tile) {
    if (ownsTile(owned, tile)) {
      Walker local(std::move(walker));
      detail::walkSegmentFrom(geometry, from, to, first, 1.0, local);
      walker = std::move(local);
    }
    return;
  }

  const double r = geometry.resolution();
  constexpr double kInf = std::numeric_limits<double>::infinity();

  // The walk at the scale of tiles: the same crossing times (computed from the same boundary
  // indices), the same order (at equal times up-steps first), gathered into stretches of owned
  // tiles. Stretches that touch are joined: each crossing time then belongs to one stretch at
  // most, so no cell is visited twice.
  int32_t step[3], boundary[3];  // the next tile boundary, in tiles
  double inv[3], t_next[3];
  for (int a = 0; a < 3; ++a) {
    const double delta = to[a] - from[a];
    step[a] = delta > 0 ? 1 : (delta < 0 ? -1 : 0);
    inv[a] = delta != 0 ? 1.0 / delta : 0.0;
    boundary[a] = tile[a] + (delta > 0);
    t_next[a] = delta != 0 ? crossingTime(double(int64_t(boundary[a]) * edge) * r, from[a], inv[a])
                           : kInf;
  }
  stretches_.clear();
  bool here = ownsTile(owned, tile);  // the current tile is owned
  bool open = here;                   // a stretch is open
  double t_in = -kInf;
  for (;;) {
    const double t = std::min(t_next[0], std::min(t_next[1], t_next[2]));
    if (!(t <= 1.0)) break;
    bool owned_on_the_way = false, moved = false;
    for (const int direction : {1, -1}) {
      bool moved_now = false;
      for (int a = 0; a < 3; ++a) {
        if (t_next[a] != t || step[a] != direction) continue;
        tile[a] += direction;
        boundary[a] += direction;
        t_next[a] = crossingTime(double(int64_t(boundary[a]) * edge) * r, from[a], inv[a]);
        moved_now = true;
      }
      if (moved_now && moved) owned_on_the_way = here;  // the tile between up- and down-steps
      if (moved_now) here = ownsTile(owned, tile), moved = true;
    }
    const bool mine = here;
    if (open && !mine) {
      stretches_.push_back({t_in, t, first});
      open = false;
    } else if (!open && mine) {
      t_in = t, open = true;
    } else if (!open && owned_on_the_way) {
      stretches_.push_back({t, t, first});  // an owned tile touched at one instant
    }
  }
  if (open) stretches_.push_back({t_in, kInf, first});
  if (stretches_.empty()) return;

  // Where each stretch resumes: in the tile before it, not owned (else the stretches would
  // have been joined). If any cannot resume, the whole walk (the walker filters it).
  // A local walker, not the reference: its state can live in registers during the walk.
  Walker local(std::move(walker));
  bool resumable = true;
  for (Stretch& s : stretches_)
    if (s.t_in != -kInf)
      resumable = resumable && detail::cellBefore(geometry, from, to, first, last, s.t_in, s.resume);
  if (!resumable) {
    detail::walkSegmentFrom(geometry, from, to, first, 1.0, local);
  } else {
    for (const Stretch& s : stretches_) {
      if (s.resume == last) break;  // the walk ended before this stretch
      detail::walkSegmentFrom(geometry, from, to, s.resume, std::min(s.t_out, 1.0), local);
    }
  }
  walker = std::move(local);
}

}  // namespace ndtom
