// What the numbers were measured on: CPU, compiler, flags (for the benchmarks' summaries).
#pragma once

#include <string>

namespace ndtom::apps {

/// "model name" of /proc/cpuinfo and the number of online CPUs, e.g. "AMD EPYC (2 CPUs)".
std::string cpuDescription();
/// Compiler, build type and flags the project (programs and core) was built with.
std::string buildDescription();

}  // namespace ndtom::apps
