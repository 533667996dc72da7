// What the numbers were measured on: CPU, compiler, flags (for doc/benchmarks.md).
#pragma once

#include <string>

namespace ndtom::bench {

/// "model name" of /proc/cpuinfo and the number of online CPUs, e.g. "AMD EPYC (2 CPUs)".
std::string cpuDescription();
/// Compiler, build type and flags this program and the core were built with.
std::string buildDescription();

}  // namespace ndtom::bench
