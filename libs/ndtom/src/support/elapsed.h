// Wall time for the reports of registration and localization.
#pragma once

#include <chrono>

namespace ndtom {

using Clock = std::chrono::steady_clock;

inline double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace ndtom
