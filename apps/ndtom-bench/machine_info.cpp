#include "machine_info.h"

#include <fstream>
#include <thread>

namespace ndtom::bench {

std::string cpuDescription() {
  std::ifstream in("/proc/cpuinfo");
  std::string model = "unknown CPU";
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  return model + " (" + std::to_string(std::thread::hardware_concurrency()) + " CPUs)";
}

std::string buildDescription() {
  // Set by apps/ndtom-bench/CMakeLists.txt from the configured toolchain.
  return std::string(NDTOM_BENCH_COMPILER) + ", " + NDTOM_BENCH_BUILD_TYPE + ", flags '" +
         NDTOM_BENCH_FLAGS + "'";
}

}  // namespace ndtom::bench
