#include "ini_values.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>

#include <cctype>
#include <cerrno>
#include <cstdlib>

namespace mrpt_ndtom::detail {

long long readInteger(const mrpt::config::CConfigFileBase& source, const std::string& section,
                      const std::string& name, long long current, long long min_value,
                      long long max_value) {
  const std::string text = source.read_string(section, name, std::to_string(current));
  char* end = nullptr;
  errno = 0;
  const long long value = std::strtoll(text.c_str(), &end, 10);
  const char* rest = end;
  while (std::isspace(static_cast<unsigned char>(*rest))) ++rest;
  const bool integer =
      end != text.c_str() && (*rest == '\0' || *rest == '#' || *rest == ';') && errno != ERANGE;
  if (!integer || value < min_value || value > max_value)
    THROW_EXCEPTION(mrpt::format("[%s] %s = %s: must be %s [%lld, %lld]", section.c_str(),
                                 name.c_str(), text.c_str(), integer ? "in" : "an integer in",
                                 min_value, max_value));
  return value;
}

}  // namespace mrpt_ndtom::detail
