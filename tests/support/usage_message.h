// For the tests of the programs' option parsing: the message a bad value is refused with.
#pragma once

#include <functional>
#include <string>

#include "ndtom_apps/option_values.h"
#include "support/thrown_message.h"

namespace ndtom::testing {

/// The message of the apps::UsageError `f` throws; "" if it throws none.
inline std::string usageMessage(const std::function<void()>& f) {
  return thrownMessage<apps::UsageError>(f);
}

}  // namespace ndtom::testing
