#include "ndtom_apps/process_memory.h"

#include <malloc.h>

#include <fstream>
#include <string>

namespace ndtom::apps {
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

bool resetPeakRss() {
  malloc_trim(0);
  std::ofstream out("/proc/self/clear_refs");
  out << "5";  // "5" resets the peak RSS (see proc(5))
  out.close();
  return bool(out) && peakRssBytes() <= currentRssBytes() + (1 << 20);
}

void keepFreedHeapForReuse() {
  // glibc's largest mmap threshold (32 MB on 64-bit): buffers below it come from the heap.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
}

}  // namespace ndtom::apps
