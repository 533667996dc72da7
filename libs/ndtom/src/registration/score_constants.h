// Magnusson's (2009, eq. 6.8) approximation of a Gaussian-plus-uniform mixture by a scaled
// Gaussian: a point's score d1·exp(−d2/2·s) for squared Mahalanobis distance s.
#pragma once

#include <cmath>

namespace ndtom::registration {

struct ScoreConstants {
  double d1 = 1;  ///< > 0 here (Magnusson's d1 with its sign flipped: scores are maximised)
  double d2 = 1;
};

/// For cells of edge `resolution` (m) and an expected outlier fraction in (0, 1).
inline ScoreConstants scoreConstants(double resolution, double outlier_ratio) {
  const double c1 = 10.0 * (1.0 - outlier_ratio);
  const double c2 = outlier_ratio / (resolution * resolution * resolution);
  const double d3 = -std::log(c2);
  const double d1 = -std::log(c1 + c2) - d3;
  const double d2 = -2.0 * std::log((-std::log(c1 * std::exp(-0.5) + c2) - d3) / d1);
  return {-d1, d2};
}

}  // namespace ndtom::registration
