// Order statistics of measured samples (times per scan, per registration, errors).
#pragma once

#include <vector>

namespace ndtom::apps {

/// q-quantile (0..1) by linear interpolation between order statistics; 0 for no samples.
double quantile(std::vector<double> samples, double q);

}  // namespace ndtom::apps
