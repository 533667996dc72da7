#include "localization/ground_columns.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <map>
#include <utility>

namespace ndtom::global {

std::vector<GroundColumn> groundColumns(const NdtMap& map, double step, double max_slope_deg) {
  const double min_normal_z = std::cos(max_slope_deg * M_PI / 180);
  std::map<std::pair<int64_t, int64_t>, double> lowest;  // ordered: deterministic output
  const bool occupancy = map.options().occupancy.enabled;
  map.forEachCell([&](const CellView& c) {
    if (!c.stats || !c.stats->hasGaussian() || (occupancy && !(c.logodds > 0.f))) return;
    const Gaussian g = map.gaussianOf(c, Covariance::Exact);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(g.covariance);
    if (std::abs(eig.eigenvectors().col(0).z()) < min_normal_z) return;
    const std::pair<int64_t, int64_t> key{int64_t(std::floor(g.mean.x() / step)),
                                          int64_t(std::floor(g.mean.y() / step))};
    const auto [it, inserted] = lowest.emplace(key, g.mean.z());
    if (!inserted) it->second = std::min(it->second, g.mean.z());
  });
  std::vector<GroundColumn> out;
  out.reserve(lowest.size());
  for (const auto& [key, z] : lowest)
    out.push_back({Eigen::Vector2d((double(key.first) + 0.5) * step,
                                   (double(key.second) + 0.5) * step),
                   z});
  return out;
}

}  // namespace ndtom::global
