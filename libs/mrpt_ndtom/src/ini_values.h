// Strict readers for .ini values where MRPT's own are lenient: read_int's atoi takes
// "4294967298" as 2 and "1e3" as 1.
#pragma once

#include <mrpt/config/CConfigFileBase.h>

#include <string>

namespace mrpt_ndtom::detail {

/// An integer in [min_value, max_value]; MRPT leaves "#" and ";" comments in the value, so
/// they may follow the number. Throws naming the section, option and text otherwise.
long long readInteger(const mrpt::config::CConfigFileBase& source, const std::string& section,
                      const std::string& name, long long current, long long min_value,
                      long long max_value);

}  // namespace mrpt_ndtom::detail
