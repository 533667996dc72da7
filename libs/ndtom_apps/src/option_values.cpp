#include "ndtom_apps/option_values.h"

#include <algorithm>
#include <sstream>

#include "ndtom/map/option_text.h"

namespace ndtom::apps {
namespace {

using ndtom::NonFinite;

// The core's reader (ndtom/map/option_text.h), as the MRPT plugin's .ini sections use it:
// a flag and a configuration file take the same texts.
template <class F>
auto asUsage(F&& parse) {
  try {
    return parse();
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

}  // namespace

double parseReal(const std::string& option, const std::string& text, bool allow_infinity) {
  return asUsage([&] {
    return ndtom::realFromText(option, text,
                               allow_infinity ? NonFinite::Infinity : NonFinite::Refused);
  });
}

int64_t parseInteger(const std::string& option, const std::string& text, int64_t min_value,
                     int64_t max_value) {
  return asUsage([&] { return ndtom::integerFromText(option, text, min_value, max_value); });
}

std::vector<int> parseLevelFactors(const std::string& option, const std::string& text) {
  const std::vector<int64_t> values = parseIntegerList(option, text, 1, 1024);
  return {values.begin(), values.end()};
}

std::vector<int64_t> parseIntegerList(const std::string& option, const std::string& text,
                                      int64_t min_value, int64_t max_value) {
  std::vector<int64_t> out;
  for (const std::string& item : splitList(text)) {
    const int64_t value = parseInteger(option, item, min_value, max_value);
    if (std::find(out.begin(), out.end(), value) != out.end())
      throw UsageError(option + ": " + item + " is listed twice");
    out.push_back(value);
  }
  if (out.empty()) throw UsageError(option + ": empty list");
  return out;
}

bool parseBool(const std::string& option, const std::string& text) {
  return asUsage([&] { return ndtom::boolFromText(option, text); });
}

bool parseOnOff(const std::string& option, const std::string& text) {
  if (text != "on" && text != "off")
    throw UsageError(option + ": expected on or off, got '" + text + "'");
  return text == "on";
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream s(text);
  // Trimmed: "1, 2" is two items, as it was when the parsers skipped leading blanks.
  for (std::string item; std::getline(s, item, ',');)
    if (!(item = trim(item)).empty()) items.push_back(item);
  return items;
}

std::string trim(const std::string& text) {
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return {};
  const size_t last = text.find_last_not_of(" \t\r\n");
  return text.substr(first, last - first + 1);
}

}  // namespace ndtom::apps
