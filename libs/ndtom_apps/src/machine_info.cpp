#include "ndtom_apps/machine_info.h"

#include <fstream>
#include <thread>

namespace ndtom::apps {

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

std::string loadAverages() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  if (!(in >> one >> five >> fifteen)) return "unknown";
  return one + " " + five + " " + fifteen;
}

std::string buildDescription() {
  // Set by libs/ndtom_apps/CMakeLists.txt from the configured toolchain.
  return std::string(NDTOM_APPS_COMPILER) + ", " + NDTOM_APPS_BUILD_TYPE + ", flags '" +
         NDTOM_APPS_FLAGS + "'";
}

}  // namespace ndtom::apps
