#include "ndtom/map/cell_rules.h"

#include <Eigen/LU>
#include <cmath>

namespace ndtom {
namespace {

// Rounding tolerance of the semi-definiteness test, relative to the diagonal: the scatter of
// N points built by RCU has rank <= N - 1, so the minors of valid cells are often 0 up to a
// few ulps (the test below bounds every term by the product of the diagonal).
constexpr double kMinorTolerance = 1e-9;

bool positiveSemiDefinite(const Eigen::Matrix3d& s) {
  for (int a = 0; a < 3; ++a)
    if (!(s(a, a) >= 0)) return false;
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b) {
      const double bound = s(a, a) * s(b, b);
      if (s(a, a) * s(b, b) - s(a, b) * s(a, b) < -kMinorTolerance * bound) return false;
    }
  // Sylvester's criterion for semi-definiteness: every principal minor, the determinant too.
  const double bound = s(0, 0) * s(1, 1) * s(2, 2);
  return s.determinant() >= -kMinorTolerance * bound;
}

}  // namespace

const char* cellProblem(const CellIndex& index, float logodds, const CellStats& stats,
                        const MapOptions& options) {
  if (!isSupportedCell(index)) return "cell index outside the supported range (|i| < 2^30)";
  const OccupancyOptions& occ = options.occupancy;
  if (!std::isfinite(logodds)) return "non-finite log-odds";
  if (!(logodds >= float(occ.logodds_min) && logodds <= float(occ.logodds_max)))
    return "log-odds outside the clamp bounds";
  if (stats.n == 0) return nullptr;
  if (occ.enabled && logodds <= 0.f) return "statistics in an empty cell";
  if (!stats.relative_mean.allFinite()) return "non-finite mean";
  const double half = 0.5 * options.resolution;
  if (!(stats.relative_mean.cwiseAbs().maxCoeff() <= half)) return "mean outside its cell";
  const Eigen::Matrix3d& s = stats.scatter;
  if (!s.allFinite()) return "non-finite scatter";
  if (s != s.transpose()) return "asymmetric scatter";
  if (stats.n == 1 && !s.isZero(0)) return "one point with a non-zero scatter";
  if (!positiveSemiDefinite(s)) return "scatter not positive semi-definite";
  // N points inside a cell of edge r spread at most N·r²/4 per axis; 4× that leaves room for
  // rounding and keeps merges and coarsening of any valid cell finite.
  const double spread_limit = double(stats.n) * options.resolution * options.resolution;
  if (!(s.diagonal().maxCoeff() <= spread_limit)) return "scatter wider than its cell";
  return nullptr;
}

}  // namespace ndtom
