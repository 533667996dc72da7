// The plugin's .ini values, read strictly through the core's reader (ndtom/map/option_text.h),
// the one ndtom-map's --config and the programs' flags use: MRPT's read_int, read_double,
// read_bool and read_enum take "4294967298" as 2, "0.2abc" as 0.2, "on" as false, "1x" as 1
// and an empty value as 0. A key that is absent keeps the current value; errors name the
// section, the key and the text in one line.
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/typemeta/TEnumType.h>

#include <optional>
#include <stdexcept>
#include <string>

#include "ndtom/map/option_text.h"

namespace mrpt_ndtom::detail {

/// The key's text, trimmed and without a " # ..." or " ; ..." comment, which MRPT leaves in
/// values (it strips only " // ..."); as there, the marker follows a blank ("2;x" is no
/// comment, and no number). nullopt if the key is absent; "" if its value is empty.
std::optional<std::string> iniText(const mrpt::config::CConfigFileBase& source,
                                   const std::string& section, const std::string& name);

/// Throws MRPT's exception with "[section] " before the message of `e`.
[[noreturn]] void throwInSection(const std::string& section, const std::exception& e);

/// parse(text) for the key, or `current` if it is absent. `parse` throws
/// std::invalid_argument naming the key, as the core's readers do.
template <class T, class Parse>
T iniValue(const mrpt::config::CConfigFileBase& source, const std::string& section,
           const std::string& name, T current, Parse&& parse) {
  const std::optional<std::string> text = iniText(source, section, name);
  if (!text) return current;
  try {
    return parse(*text);
  } catch (const std::invalid_argument& e) {
    throwInSection(section, e);
  }
}

double iniReal(const mrpt::config::CConfigFileBase& source, const std::string& section,
               const std::string& name, double current,
               ndtom::NonFinite allowed = ndtom::NonFinite::Refused);

long long iniInteger(const mrpt::config::CConfigFileBase& source, const std::string& section,
                     const std::string& name, long long current, long long min_value,
                     long long max_value);

bool iniBool(const mrpt::config::CConfigFileBase& source, const std::string& section,
             const std::string& name, bool current);

/// One of the enum's MRPT names, or the number of one (as read_enum takes them); other
/// numbers are refused here, before they are cast to the enum.
template <class E>
E iniEnum(const mrpt::config::CConfigFileBase& source, const std::string& section,
          const std::string& name, E current) {
  return iniValue(source, section, name, current, [&](const std::string& text) {
    const auto& names = mrpt::typemeta::TEnumType<E>::getBimap().m_k2v;
    std::string choices;
    size_t i = 0;
    for (const auto& [value, word] : names) {
      if (text == word || text == std::to_string(int(value))) return value;
      choices += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + word;
      ++i;
    }
    throw std::invalid_argument(name + ": expected " + choices + ", got '" + text + "'");
  });
}

}  // namespace mrpt_ndtom::detail
