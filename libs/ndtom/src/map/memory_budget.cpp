#include "ndtom/map/memory_budget.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "ndtom_internal/input_file.h"

namespace ndtom {

namespace {

std::string message(const std::string& what, uint64_t needed, uint64_t budget) {
  std::string need = megabytes(needed), have = megabytes(budget);
  if (need == have) {  // more digits, so that the message shows the difference
    char text[64];
    std::snprintf(text, sizeof(text), "%.6f MB", double(needed) / 1e6);
    need = text;
    std::snprintf(text, sizeof(text), "%.6f MB", double(budget) / 1e6);
    have = text;
  }
  return what + " needs " + need + " or more, over the memory budget of " + have +
         " (memory_budget)";
}

}  // namespace

MemoryBudgetError::MemoryBudgetError(const std::string& what, uint64_t needed, uint64_t budget)
    : std::runtime_error(message(what, needed, budget)), needed_(needed), budget_(budget) {}

uint64_t defaultMemoryBudget() {
  static const uint64_t budget = [] {
    constexpr uint64_t kCap = 512000000;
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0) return kCap;
    return std::max(kMinMemoryBudget, std::min(kCap, uint64_t(pages) * uint64_t(page) / 4));
  }();
  return budget;
}

}  // namespace ndtom
