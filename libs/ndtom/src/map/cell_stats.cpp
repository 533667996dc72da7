#include "ndtom/map/cell_stats.h"

#include <algorithm>

namespace ndtom {
namespace {

// s += w·d·dᵀ, computed once per upper-triangle entry and mirrored: Eigen's own expression
// may associate (w·d_i)·d_j and (w·d_j)·d_i differently, leaving S asymmetric in the last bit.
void addWeightedOuterProduct(Eigen::Matrix3d& s, const Eigen::Vector3d& d, double w) {
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      s(i, j) += w * (d[i] * d[j]);
      s(j, i) = s(i, j);
    }
}

}  // namespace

void CellStats::merge(const CellStats& other) {
  if (other.n == 0) return;
  if (n == 0) {
    *this = other;
    return;
  }
  const double m = n, k = other.n, total = m + k;
  const Eigen::Vector3d delta = other.relative_mean - relative_mean;
  // Eq. 11: S = S_x + S_y + mk/(m+k) (μ_x − μ_y)(μ_x − μ_y)ᵀ
  scatter += other.scatter;
  addWeightedOuterProduct(scatter, delta, m * k / total);
  // Eq. 2, written as an increment so equal means stay bit-exact.
  relative_mean += (k / total) * delta;
  const uint64_t count = uint64_t(n) + other.n;
  if (count > kMaxCellPoints) {
    // N saturates: shrink S with it, so S / (N − 1) stays the covariance and S stays within
    // what N points can spread in the cell (cell_rules.h).
    scatter *= double(kMaxCellPoints) / double(count);
  }
  n = uint32_t(std::min<uint64_t>(count, kMaxCellPoints));
}

CellStats CellStats::fromPoints(const std::vector<Eigen::Vector3d>& relative_points) {
  CellStats s;
  if (relative_points.empty()) return s;
  s.n = uint32_t(std::min<uint64_t>(relative_points.size(), kMaxCellPoints));
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : relative_points) sum += p;
  s.relative_mean = sum / double(relative_points.size());
  for (const auto& p : relative_points) {
    addWeightedOuterProduct(s.scatter, p - s.relative_mean, 1.0);
  }
  return s;
}

}  // namespace ndtom
