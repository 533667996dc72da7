#include "live_map.h"

#include <cmath>

#include "ndtom/map/block_grid.h"
#include "ndtom/scale/block_moves.h"

namespace ndtom::localizer {
namespace {

bool blockWithin(const ndtom::CellIndex& b, const Eigen::Vector3d& centre, double radius,
                 double block_edge) {
  double squared = 0;
  for (int a = 0; a < 2; ++a) {  // x, y: a region is a column of the world
    const double lo = double(b[a]) * block_edge, hi = lo + block_edge;
    const double d = centre[a] < lo ? lo - centre[a] : (centre[a] > hi ? centre[a] - hi : 0.0);
    squared += d * d;
  }
  return squared <= radius * radius;
}

// `into` gains every cell of `from` it does not know (the same resolution).
void addUnknownCells(ndtom::NdtMap& into, const ndtom::NdtMap& from) {
  from.forEachCellOrdered([&](const ndtom::CellView& c) {
    if (into.cell(c.index)) return;
    into.setCell(c.index, c.logodds, c.stats ? *c.stats : ndtom::CellStats{});
  });
  into.shrinkToFit();
}

// `into` gains the cells of `from` it does not know, and those where `from` has a Gaussian
// and it has none: where both hold a Gaussian, `into`'s wins.
void addCellsThePriorLacks(ndtom::NdtMap& into, const ndtom::NdtMap& from) {
  from.forEachCellOrdered([&](const ndtom::CellView& c) {
    const auto mine = into.cell(c.index);
    const bool gaussian = c.stats && c.stats->hasGaussian();
    if (mine && !(gaussian && !(mine->stats && mine->stats->hasGaussian()))) return;
    into.setCell(c.index, c.logodds, c.stats ? *c.stats : ndtom::CellStats{});
  });
}

}  // namespace

LiveMap::LiveMap(const ndtom::MapOptions& options, const LiveMapSettings& settings)
    : settings_(settings), live_(options), dropped_(options), target_(options) {}

const ndtom::NdtMap& LiveMap::targetAround(const ndtom::NdtMap& prior,
                                            const Eigen::Isometry3d& sensor) {
  ++scans_since_cut_;
  const bool changed = target_prior_revision_ != prior.revision() ||
                       target_live_revision_ != live_.revision();
  if (cut_at_ && !(changed && settings_.refresh.due(*cut_at_, sensor, scans_since_cut_)))
    return target_;
  const double block_edge = ndtom::kBlockEdge * prior.options().resolution;
  const Eigen::Vector3d centre = sensor.translation();
  const auto near = [&](const ndtom::CellIndex& b) {
    return blockWithin(b, centre, settings_.radius, block_edge);
  };
  target_ = ndtom::copyBlocks(prior, near);
  addCellsThePriorLacks(target_, ndtom::copyBlocks(live_, near));
  target_prior_revision_ = prior.revision();
  target_live_revision_ = live_.revision();
  cut_at_ = sensor;
  scans_since_cut_ = 0;
  return target_;
}

void LiveMap::insert(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& origin) {
  live_.insertScan(points, origin);
  const double block_edge = ndtom::kBlockEdge * live_.options().resolution;
  // Kept a little wider than the target's region: what it may need next.
  const double keep = 1.5 * settings_.radius;
  const ndtom::NdtMap behind = ndtom::extractBlocks(live_, [&](const ndtom::CellIndex& b) {
    return !blockWithin(b, origin, keep, block_edge);
  });
  if (settings_.keep_all) addUnknownCells(dropped_, behind);
}

LiveMap::Shares LiveMap::sharesOf(const ndtom::NdtMap& prior,
                                  const std::vector<Eigen::Vector3d>& points) const {
  Shares s;
  if (points.empty()) return s;
  size_t in_prior = 0, in_live = 0;
  for (const Eigen::Vector3d& p : points) {
    const auto pc = prior.cellAt(p);
    if (pc && pc->stats && pc->stats->hasGaussian()) {
      ++in_prior;
      continue;
    }
    const auto lc = live_.cellAt(p);
    in_live += !pc && lc && lc->stats && lc->stats->hasGaussian();
  }
  s.prior = double(in_prior) / double(points.size());
  s.live = double(in_live) / double(points.size());
  return s;
}

ndtom::NdtMap LiveMap::extended(const ndtom::NdtMap& prior) const {
  ndtom::NdtMap out = prior;
  addUnknownCells(out, live_);
  addUnknownCells(out, dropped_);
  return out;
}

}  // namespace ndtom::localizer
