#include "process_memory.h"

#include <fstream>
#include <string>

namespace ndtom::mapper {
namespace {

size_t statusField(const std::string& name) {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(name + ":", 0) == 0) return std::stoul(line.substr(name.size() + 1)) * 1024;
  return 0;  // the values are in kB
}

}  // namespace

size_t currentRssBytes() {
  return statusField("VmRSS");
}

size_t peakRssBytes() {
  return statusField("VmHWM");
}

}  // namespace ndtom::mapper
