#include "ndtom/cell_stats.h"

namespace ndtom {

void CellStats::merge(const CellStats& other) {
  if (other.n == 0) return;
  if (n == 0) {
    *this = other;
    return;
  }
  const double m = n, k = other.n, total = m + k;
  const Eigen::Vector3d delta = other.mean - mean;
  // Eq. 11: S = S_x + S_y + mk/(m+k) (μ_x − μ_y)(μ_x − μ_y)ᵀ
  scatter += other.scatter + (m * k / total) * (delta * delta.transpose());
  // Eq. 2, written as an increment so equal means stay bit-exact.
  mean += (k / total) * delta;
  n += other.n;
}

CellStats CellStats::fromPoints(const std::vector<Eigen::Vector3d>& relative_points) {
  CellStats s;
  if (relative_points.empty()) return s;
  s.n = uint32_t(relative_points.size());
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : relative_points) sum += p;
  s.mean = sum / double(s.n);
  for (const auto& p : relative_points) {
    const Eigen::Vector3d d = p - s.mean;
    s.scatter += d * d.transpose();
  }
  return s;
}

}  // namespace ndtom
