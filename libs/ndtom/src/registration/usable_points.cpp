#include "registration/usable_points.h"

#include "ndtom/map/cell_index.h"

namespace ndtom::registration {

std::vector<Eigen::Vector3d> usablePoints(const std::vector<Eigen::Vector3d>& scan,
                                          double min_range, double max_range, double cell_size) {
  const GridGeometry grid(cell_size);
  std::vector<Eigen::Vector3d> out;
  out.reserve(scan.size());
  for (const Eigen::Vector3d& p : scan) {
    if (!grid.inRange(p)) continue;  // also drops NaN and inf
    const double range = p.norm();
    if (range >= min_range && range <= max_range && range < kMaxUsableRange) out.push_back(p);
  }
  return out;
}

}  // namespace ndtom::registration
