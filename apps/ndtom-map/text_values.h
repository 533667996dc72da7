// Strict parsing of option values: the whole text must be the value, or UsageError names the
// option and the text. (MRPT's own .ini readers turn "abc" into 0 without a word.)
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace ndtom::mapper {

/// A bad command line or configuration value; the message is one line naming the option.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A real number; "inf" is accepted only if `allow_infinity`.
double parseReal(const std::string& option, const std::string& text, bool allow_infinity = false);
/// An integer in [min_value, max_value].
int64_t parseInteger(const std::string& option, const std::string& text, int64_t min_value,
                     int64_t max_value);
/// true/yes/1 or false/no/0, any case (the words MRPT's read_bool understands alike).
bool parseBool(const std::string& option, const std::string& text);

/// `text` without leading and trailing blanks.
std::string trim(const std::string& text);

/// The message of an exception on one line: for MRPT's exceptions, whose what() spans a
/// banner, the message, its source location and a backtrace, only the message.
std::string oneLineMessage(const std::exception& e);

}  // namespace ndtom::mapper
