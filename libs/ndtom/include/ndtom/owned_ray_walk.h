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
  /// walkRay's walker interface. The walker must itself ignore visits of cells outside owned
  /// tiles: each stretch of owned tiles is walked from the cell before it (already visited,
  /// in another rank's tile) to the cell after it. Over all ranks, each cell of
  /// walkRay(from, to) is visited in exactly one rank's owned tile.
  template <class Walker>
  void walk(const GridGeometry& geometry, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
            const TileOwnership& owned, Walker& walker);

 private:
  struct Crossing {  // of a tile boundary
    double t;
    int axis, step;
  };
  struct Stretch {       // of consecutive owned tiles
    double t_in, t_out;  ///< entered at t_in (-inf: at the start), left at t_out (+inf: never)
    CellIndex resume;    ///< the walk's cell after every crossing before t_in
  };
  std::vector<Crossing> crossings_;
  std::vector<Stretch> stretches_;
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
      const double guess = std::floor((from[a] + t * delta) / r);  // corrected below
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
  const double r = geometry.resolution();
  CellIndex tile{floorDiv(first.x, edge), floorDiv(first.y, edge), floorDiv(first.z, edge)};

  // The tile boundaries the walk crosses, at the walk's own crossing times.
  crossings_.clear();
  for (int a = 0; a < 3; ++a) {
    const double delta = to[a] - from[a];
    if (delta == 0) continue;
    const double inv = 1.0 / delta;
    const int step = delta > 0 ? 1 : -1;
    for (int32_t boundary_tile = delta > 0 ? tile[a] + 1 : tile[a];; boundary_tile += step) {
      const double t = crossingTime(double(int64_t(boundary_tile) * edge) * r, from[a], inv);
      if (!(t <= 1.0)) break;
      crossings_.push_back({t, a, step});
    }
  }
  std::sort(crossings_.begin(), crossings_.end(),
            [](const Crossing& u, const Crossing& v) { return u.t < v.t; });

  // The tiles in the walk's order (at equal times up-steps first, as the walk does), gathered
  // into stretches of owned tiles. Stretches that touch are joined: each crossing time then
  // belongs to one stretch at most, so no cell is visited twice.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  stretches_.clear();
  auto enter = [&](double t) {
    const bool mine = owned.ownsTile(tile);
    const bool open = !stretches_.empty() && stretches_.back().t_out == kInf;
    if (mine && !open) {
      if (!stretches_.empty() && stretches_.back().t_out >= t)
        stretches_.back().t_out = kInf;  // reopened at the instant it closed
      else
        stretches_.push_back({t, kInf, first});
    } else if (!mine && open) {
      stretches_.back().t_out = t;
    }
  };
  enter(-kInf);
  for (size_t i = 0; i < crossings_.size();) {
    size_t j = i;
    while (j < crossings_.size() && crossings_[j].t == crossings_[i].t) ++j;
    for (int step : {1, -1}) {
      bool moved = false;
      for (size_t k = i; k < j; ++k)
        if (crossings_[k].step == step) tile[crossings_[k].axis] += step, moved = true;
      if (moved) enter(crossings_[i].t);
    }
    i = j;
  }

  // Where each stretch resumes: in the tile before it, not owned (else the stretches would
  // have been joined). If any cannot resume, the whole walk (the walker filters it).
  for (Stretch& s : stretches_) {
    if (s.t_in == -kInf) continue;
    if (!detail::cellBefore(geometry, from, to, first, last, s.t_in, s.resume)) {
      detail::walkSegmentFrom(geometry, from, to, first, 1.0, walker);
      return;
    }
  }
  for (const Stretch& s : stretches_) {
    if (s.resume == last) return;  // the walk ended before this stretch
    detail::walkSegmentFrom(geometry, from, to, s.resume, std::min(s.t_out, 1.0), walker);
  }
}

}  // namespace ndtom
