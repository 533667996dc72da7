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

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  const size_t k =
      std::min(values.size() - 1, size_t(std::ceil(q * double(values.size()))) - (q > 0 ? 1 : 0));
  std::nth_element(values.begin(), values.begin() + long(k), values.end());
  return values[k];
}

}  // namespace ndtom::apps
