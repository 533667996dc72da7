// Stage 3 of a scan's insertion: the sorted ray ends gathered per cell. A hit group's points
// give N_p (Eq. 12) and the batch that RCU merges into the cell (Eq. 2, 11). Private to the
// library.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "insertion/classify_points.h"
#include "insertion/ray_ends.h"
#include "insertion/scan_context.h"
#include "map/map_block.h"
#include "ndtom/map/cell_stats.h"

namespace ndtom {

/// Rays that end in one cell: the unit of Eq. 12's N_p and of the per-hit-cell ray mode.
struct EndGroup {
  CellIndex cell;
  uint32_t begin;  ///< its rays' ends are sorted_ends[begin, begin + count)
  uint32_t count;
  bool hit;
  Eigen::Vector3d relative_mean;  ///< of the ray ends, from the cell centre (per-hit-cell mode)
  Eigen::Vector3d mean_end;  ///< the same in the world frame: that mode's ray end
};

/// A map block with hits in this scan: the unit of the hit update, owned by one thread.
struct HitBlock {
  size_t first_group, last_group;  ///< from its first hit group to its last (in `groups`)
  MapBlock::Mask hits;             ///< its hit cells
  uint64_t number = 0;             ///< its block number in the sort key (denseIndex / 512)
};

struct EndGroups {
  std::vector<Eigen::Vector3d> sorted_ends;  ///< the ray ends in sorted order
  std::vector<EndGroup> groups;              ///< in sorted order: a block's in offset order
  std::vector<HitBlock> hit_blocks;          ///< in the same order
  std::vector<std::vector<HitBlock>> part_hit_blocks;  ///< scratch: each thread's, in order
  bool has_means = false;                    ///< EndGroup::relative_mean and mean_end are set

  const CellIndex& blockCell(const HitBlock& h) const { return groups[h.first_group].cell; }
};

/// Whether groupEnds computes each group's mean end: only the per-hit-cell ray mode aims at it.
enum class GroupMeans : uint8_t { Skip, Compute };

/// Groups the sorted ends into `out`, with each group's mean if `means` is Compute; counts
/// the hit cells in `report`.
void groupEnds(const ScanContext& scan, const ClassifiedPoints& points, const SortedRayEnds& sorted,
               GroupMeans means, EndGroups& out, InsertionReport& report);

/// Two-pass statistics (Eq. 1) of a group's points, relative to its cell's centre.
inline CellStats groupStats(const EndGroups& groups, const EndGroup& g,
                            const GridGeometry& geometry) {
  const Eigen::Vector3d centre = geometry.cellCenter(g.cell);
  const uint32_t end = g.begin + g.count;
  const std::vector<Eigen::Vector3d>& ends = groups.sorted_ends;
  CellStats stats;
  stats.n = g.count;
  if (groups.has_means) {
    stats.relative_mean = g.relative_mean;
  } else {
    for (uint32_t i = g.begin; i < end; ++i) stats.relative_mean += ends[i] - centre;
    stats.relative_mean /= double(g.count);
  }
  // Upper triangle in scalars: Eigen's d·dᵀ here goes through the stack and stalls on store
  // forwarding. Same sums in the same order, so the same bits.
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  for (uint32_t i = g.begin; i < end; ++i) {
    const Eigen::Vector3d d = ends[i] - centre - stats.relative_mean;
    xx += d.x() * d.x(), xy += d.x() * d.y(), xz += d.x() * d.z();
    yy += d.y() * d.y(), yz += d.y() * d.z(), zz += d.z() * d.z();
  }
  stats.scatter << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  stats.clampMean(0.5 * geometry.resolution());
  return stats;
}

}  // namespace ndtom
