#include "ini_values.h"

#include <mrpt/core/exceptions.h>

#include <cctype>

namespace mrpt_ndtom::detail {

std::optional<std::string> iniText(const mrpt::config::CConfigFileBase& source,
                                   const std::string& section, const std::string& name) {
  if (!source.keyExists(section, name)) return std::nullopt;
  std::string text = source.read_string(section, name, "");
  const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  for (size_t i = 0; i < text.size(); ++i)
    if ((text[i] == '#' || text[i] == ';') && (i == 0 || blank(text[i - 1]))) {
      text.erase(i);
      break;
    }
  while (!text.empty() && blank(text.back())) text.pop_back();
  return text;
}

void throwInSection(const std::string& section, const std::exception& e) {
  THROW_EXCEPTION("[" + section + "] " + e.what());
}

double iniReal(const mrpt::config::CConfigFileBase& source, const std::string& section,
               const std::string& name, double current, ndtom::NonFinite allowed) {
  return iniValue(source, section, name, current, [&](const std::string& text) {
    return ndtom::realFromText(name, text, allowed);
  });
}

long long iniInteger(const mrpt::config::CConfigFileBase& source, const std::string& section,
                     const std::string& name, long long current, long long min_value,
                     long long max_value) {
  return iniValue(source, section, name, current, [&](const std::string& text) {
    return (long long)ndtom::integerFromText(name, text, min_value, max_value);
  });
}

bool iniBool(const mrpt::config::CConfigFileBase& source, const std::string& section,
             const std::string& name, bool current) {
  return iniValue(source, section, name, current,
                  [&](const std::string& text) { return ndtom::boolFromText(name, text); });
}

}  // namespace mrpt_ndtom::detail
