// For the tests of the programs' option parsing: the message a bad value is refused with.
#pragma once

#include <functional>
#include <string>

#include "ndtom_apps/option_values.h"

namespace ndtom::testing {

/// The message of the apps::UsageError `f` throws; "" if it throws none.
inline std::string usageMessage(const std::function<void()>& f) {
  try {
    f();
  } catch (const apps::UsageError& e) {
    return e.what();
  }
  return "";
}

}  // namespace ndtom::testing
