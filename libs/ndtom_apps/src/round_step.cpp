#include "ndtom_apps/round_step.h"

#include <cmath>
#include <cstdio>

namespace ndtom::apps {

double roundStep(double span, int parts) {
  const double raw = span / parts;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0})
    if (m * power >= raw) return m * power;
  return 10 * power;
}

std::string stepLabel(double value, double step) {
  char text[32];
  const int decimals = step >= 1 ? 0 : (step >= 0.1 ? 1 : 2);
  if (std::abs(value) < 1e-3 * step) value = 0;
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

}  // namespace ndtom::apps
