#include "ndtom_apps/option_values.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

namespace ndtom::apps {

double parseReal(const std::string& option, const std::string& text, bool allow_infinity) {
  size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {  // no number at all, or out of range ("1e999")
    used = 0;
  }
  if (text.empty() || used != text.size() || std::isnan(value))
    throw UsageError(option + ": not a number: '" + text + "'");
  if (std::isinf(value) && !allow_infinity)
    throw UsageError(option + ": must be finite, got '" + text + "'");
  return value;
}

int64_t parseInteger(const std::string& option, const std::string& text, int64_t min_value,
                     int64_t max_value) {
  size_t used = 0;
  long long value = 0;
  try {
    value = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (text.empty() || used != text.size())
    throw UsageError(option + ": not an integer: '" + text + "'");
  if (value < min_value || value > max_value)
    throw UsageError(option + " = " + text + ": must be in [" + std::to_string(min_value) + ", " +
                     std::to_string(max_value) + "]");
  return value;
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
  std::string lower = text;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (lower == "true" || lower == "yes" || lower == "1") return true;
  if (lower == "false" || lower == "no" || lower == "0") return false;
  throw UsageError(option + ": expected true or false, got '" + text + "'");
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream s(text);
  for (std::string item; std::getline(s, item, ',');)
    if (!item.empty()) items.push_back(item);
  return items;
}

std::string trim(const std::string& text) {
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return {};
  const size_t last = text.find_last_not_of(" \t\r\n");
  return text.substr(first, last - first + 1);
}

}  // namespace ndtom::apps
