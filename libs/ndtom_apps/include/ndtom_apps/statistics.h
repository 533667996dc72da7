// Order statistics of measured samples (times per scan, per registration, errors).
#pragma once

#include <vector>

namespace ndtom::apps {

/// q-quantile (0..1) by linear interpolation between order statistics; 0 for no samples.
double quantile(std::vector<double> samples, double q);

/// Value at fraction q in [0, 1] of the sorted values, by nearest rank (one of the samples,
/// as the summaries report times); 0 for no samples.
double percentile(std::vector<double> values, double q);

}  // namespace ndtom::apps
