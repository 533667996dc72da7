// For the tests of refusals: the message an exception was thrown with.
#pragma once

#include <exception>
#include <functional>
#include <string>

namespace ndtom::testing {

/// The message of the `Error` that `f` throws; "" if it throws none.
template <typename Error = std::exception>
std::string thrownMessage(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace ndtom::testing
