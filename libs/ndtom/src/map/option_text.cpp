#include "ndtom/map/option_text.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ndtom {
namespace {

// from_chars, unlike strtod and stoll, takes no blanks, no hexadecimal and no locale's comma;
// its one gap is a leading '+', which people write ("+1e-3").
const char* afterPlus(const std::string& text) {
  const char* first = text.data();
  if (text.size() > 1 && text[0] == '+' && text[1] != '+' && text[1] != '-') ++first;
  return first;
}

std::string lowerCase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return text;
}

// A bound of a row as an integer limit; an infinite bound is no limit.
int64_t integerBound(double bound) {
  if (bound <= double(std::numeric_limits<int64_t>::min()))
    return std::numeric_limits<int64_t>::min();
  if (bound >= double(std::numeric_limits<int64_t>::max()))
    return std::numeric_limits<int64_t>::max();
  return int64_t(bound);
}

}  // namespace

double realFromText(const std::string& name, const std::string& text, NonFinite allowed) {
  const char* first = afterPlus(text);
  const char* last = text.data() + text.size();
  double value = 0;
  const auto [end, error] = std::from_chars(first, last, value);
  if (error == std::errc::result_out_of_range && end == last)  // "1e400", "1e-400"
    throw std::invalid_argument(name + ": out of a double's range: '" + text + "'");
  const bool nan_allowed = allowed == NonFinite::Nan;
  if (text.empty() || error != std::errc() || end != last || (std::isnan(value) && !nan_allowed))
    throw std::invalid_argument(name + ": not a number: '" + text + "'");
  if (std::isinf(value) && allowed != NonFinite::Infinity)
    throw std::invalid_argument(name + ": must be finite, got '" + text + "'");
  return value;
}

int64_t integerFromText(const std::string& name, const std::string& text, int64_t min_value,
                        int64_t max_value) {
  const char* first = afterPlus(text);
  const char* last = text.data() + text.size();
  long long value = 0;
  const auto [end, error] = std::from_chars(first, last, value, 10);
  const bool overflow = error == std::errc::result_out_of_range && end == last;
  if (!overflow && (text.empty() || error != std::errc() || end != last))
    throw std::invalid_argument(name + ": not an integer: '" + text + "'");
  if (overflow || value < min_value || value > max_value)
    throw std::invalid_argument(name + " = " + text + ": must be in [" + std::to_string(min_value) +
                                ", " + std::to_string(max_value) + "]");
  return value;
}

bool boolFromText(const std::string& name, const std::string& text) {
  const std::string word = lowerCase(text);
  if (word == "true" || word == "yes" || word == "1") return true;
  if (word == "false" || word == "no" || word == "0") return false;
  throw std::invalid_argument(name + ": expected true or false, got '" + text + "'");
}

double optionFromText(const OptionRow& row, const std::string& name, const std::string& text) {
  switch (row.type) {
    case OptionType::Real: {
      const bool infinite = row.bounds.contains(INFINITY) || row.bounds.contains(-INFINITY);
      return realFromText(name, text, infinite ? NonFinite::Infinity : NonFinite::Refused);
    }
    case OptionType::Integer:
      return double(
          integerFromText(name, text, integerBound(row.bounds.min), integerBound(row.bounds.max)));
    case OptionType::Bool:
      return boolFromText(name, text) ? 1.0 : 0.0;
    case OptionType::Enum:
      // By name, as files and --help write it, or by number, as MRPT's read_enum also takes it.
      for (size_t i = 0; i < row.names.size() && row.names[i]; ++i)
        if (text == row.names[i] || text == std::to_string(i)) return double(i);
      throw std::invalid_argument(name + ": expected " + optionChoices(row) + ", got '" + text +
                                  "'");
  }
  throw std::invalid_argument(name + ": unknown option type");
}

}  // namespace ndtom
