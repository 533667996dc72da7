#include "ndtom_apps/statistics.h"

#include <algorithm>
#include <cmath>

namespace ndtom::apps {

double quantile(std::vector<double> samples, double q) {
  if (samples.empty()) return 0;
  std::sort(samples.begin(), samples.end());
  const double pos = q * double(samples.size() - 1);
  const size_t i = size_t(std::floor(pos));
  if (i + 1 >= samples.size()) return samples.back();
  return samples[i] + (pos - double(i)) * (samples[i + 1] - samples[i]);
}

}  // namespace ndtom::apps
