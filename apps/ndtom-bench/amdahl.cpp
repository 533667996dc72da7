#include "amdahl.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ndtom::bench {

double amdahlSpeedup(double parallel_fraction, double threads) {
  const double p = parallel_fraction;
  if (!(p >= 0 && p <= 1))
    throw std::invalid_argument("amdahlSpeedup: parallel fraction " + std::to_string(p) +
                                " is not in [0, 1]");
  if (!(threads >= 1 && std::isfinite(threads)))
    throw std::invalid_argument("amdahlSpeedup: " + std::to_string(threads) +
                                " threads, expected a finite count >= 1");
  return 1 / ((1 - p) + p / threads);
}

double spinningCpuRatio(double parallel_fraction, double threads) {
  return threads / amdahlSpeedup(parallel_fraction, threads);  // also checks the arguments
}

double parallelFraction(double parallel_seconds, double total_seconds) {
  if (!(parallel_seconds >= 0 && std::isfinite(parallel_seconds)) ||
      !(total_seconds > 0 && std::isfinite(total_seconds)))
    throw std::invalid_argument("parallelFraction: " + std::to_string(parallel_seconds) +
                                " s parallel of " + std::to_string(total_seconds) +
                                " s: expected finite times, a total > 0");
  return std::min(1.0, parallel_seconds / total_seconds);
}

}  // namespace ndtom::bench
