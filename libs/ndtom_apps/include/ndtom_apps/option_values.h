// Strict parsing of option values, from the command line or a configuration file: the whole
// text must be the value, or UsageError names the option and the text. The core's reader
// (ndtom/map/option_text.h), which the MRPT plugin's .ini sections use too, does the parsing.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace ndtom::apps {

/// A bad command line or configuration value; the message is one line naming the option.
/// Programs exit with status 2 on it (see runProgram).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A real number; never NaN; "inf" only if `allow_infinity`; out of double's range is an error.
double parseReal(const std::string& option, const std::string& text, bool allow_infinity = false);
/// An integer in [min_value, max_value].
int64_t parseInteger(const std::string& option, const std::string& text, int64_t min_value,
                     int64_t max_value);
/// The integers of a comma-separated list, each in [min_value, max_value]; a value given
/// twice or an empty list is an error.
std::vector<int64_t> parseIntegerList(const std::string& option, const std::string& text,
                                      int64_t min_value, int64_t max_value);
/// Registration pyramid levels ("16,8,4,2,1"), each in [1, 1024], as multiples of the map's
/// cell; their order is checked with the registration's options.
std::vector<int> parseLevelFactors(const std::string& option, const std::string& text);
/// true/yes/1 or false/no/0, any case, as the MRPT plugin reads its .ini files.
bool parseBool(const std::string& option, const std::string& text);
/// "on" or "off" exactly (the programs' switches: --loop-closure, --live-map, ...).
bool parseOnOff(const std::string& option, const std::string& text);

/// The items of a comma-separated list, trimmed, empty ones left out ("0.1,, 0.2," has two).
std::vector<std::string> splitList(const std::string& text);

/// `text` without leading and trailing blanks.
std::string trim(const std::string& text);

}  // namespace ndtom::apps
