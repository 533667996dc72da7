#include "ndtom_apps/height_colors.h"

#include <mrpt/img/color_maps.h>

#include <algorithm>
#include <vector>

#include "ndtom/map/map_queries.h"

namespace ndtom::apps {

double HeightScale::fraction(double z) const {
  return std::clamp((z - z_min) / (z_max - z_min), 0.0, 1.0);
}

cv::Scalar HeightScale::bgr(double z) const {
  float r = 0, g = 0, b = 0;
  mrpt::img::colormap(mrpt::img::cmJET, float(fraction(z)), r, g, b);
  return cv::Scalar(255.0 * b, 255.0 * g, 255.0 * r);
}

HeightScale heightScaleOf(const ndtom::NdtMap& map) {
  std::vector<double> z;
  map.forEachCell([&](const ndtom::CellView& c) {
    // The mean only: the exact covariance, not the regularised one (an eigendecomposition
    // per Gaussian), and the same mean.
    if (ndtom::isOccupiedGaussian(map, c))
      z.push_back(map.gaussianOf(c, ndtom::Covariance::Exact).mean.z());
  });
  HeightScale scale;
  if (z.empty()) return scale;
  const size_t lo = z.size() / 50, hi = z.size() - 1 - z.size() / 50;
  std::nth_element(z.begin(), z.begin() + long(lo), z.end());
  scale.z_min = z[lo];
  std::nth_element(z.begin(), z.begin() + long(hi), z.end());
  scale.z_max = z[hi];
  if (!(scale.z_max > scale.z_min)) {  // a flat map (2D scans): its height mid-scale
    scale.z_min -= 0.5;
    scale.z_max += 0.5;
  }
  return scale;
}

}  // namespace ndtom::apps
