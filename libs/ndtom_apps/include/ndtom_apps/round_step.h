// Round numbers for axes, colour bars and scale bars: steps of 1, 2 or 5 times a power of
// ten, and labels with as many decimals as the step needs.
#pragma once

#include <string>

namespace ndtom::apps {

/// The smallest step of 1, 2 or 5 times a power of ten that splits `span` (> 0) into at
/// most `parts` parts.
double roundStep(double span, int parts);

/// `value` with the decimals a multiple of `step` needs (0, 1 or 2); never "-0".
std::string stepLabel(double value, double step);

}  // namespace ndtom::apps
