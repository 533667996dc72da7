// What the numbers were measured on: CPU, compiler, flags (for the benchmarks' summaries).
#pragma once

#include <string>

namespace ndtom::apps {

/// "model name" of /proc/cpuinfo and the number of online CPUs, e.g. "AMD EPYC (2 CPUs)".
std::string cpuDescription();
/// The load averages over 1, 5 and 15 minutes (/proc/loadavg), e.g. "0.52 0.58 0.59":
/// on a shared machine, how many other processes competed for the CPUs; "unknown" if absent.
std::string loadAverages();
/// Compiler, build type and flags the project (programs and core) was built with.
std::string buildDescription();

}  // namespace ndtom::apps
