// The one way the core rejects a bad option value: std::invalid_argument("<option> = <value>:
// <why>"), so every message names the option and what it was given.
#pragma once

#include <sstream>
#include <stdexcept>

namespace ndtom {

[[noreturn]] inline void failOption(const char* option, double value, const char* why) {
  std::ostringstream msg;
  msg << option << " = " << value << ": " << why;
  throw std::invalid_argument(msg.str());
}

}  // namespace ndtom
