// Option values from text, strictly: the whole text is the value, or std::invalid_argument
// names the option and shows the text. The one reader behind the MRPT plugin's .ini sections,
// ndtom-map's --config and the programs' flags: std::atof, atoi and MRPT's read_* take
// "0.2abc" as 0.2, "4294967298" as 2, "on" as false and an empty value as 0 without a word.
//
// Messages are one line: "<name>: not a number: '<text>'", "<name> = <text>: must be in
// [a, b]"; the caller's `name` says where the text came from ("key", "--flag").
#pragma once

#include <cstdint>
#include <string>

#include "ndtom/map/option_table.h"

namespace ndtom {

/// The non-finite reals an option may take (inf: "no limit", nan: "choose for me").
enum class NonFinite { Refused, Infinity, Nan };

/// A decimal real, optionally in scientific notation ("0.25", "-3", "+1e-3"), or "inf"/"nan"
/// (any case) where `allowed`. No blanks, no hexadecimal; beyond double's range is an error,
/// not ±inf or 0.
double realFromText(const std::string& name, const std::string& text,
                    NonFinite allowed = NonFinite::Refused);

/// A decimal integer in [min_value, max_value] ("-0" is 0, which the range may refuse).
int64_t integerFromText(const std::string& name, const std::string& text, int64_t min_value,
                        int64_t max_value);

/// true, yes or 1; false, no or 0; any case: the words of MRPT's read_bool, without its atoi
/// fallback that reads "on" as false and "2" as true.
bool boolFromText(const std::string& name, const std::string& text);

/// A value of the row's type: a Real (infinite only if the bounds hold an infinity), an
/// Integer within the bounds, a Bool, or an Enum by name or number. The caller checks the
/// bounds (checkOptionValue), whose message names the row.
double optionFromText(const OptionRow& row, const std::string& name, const std::string& text);

}  // namespace ndtom
