#include "ndtom_apps/run_budget.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ndtom/map/memory_budget.h"
#include "ndtom_apps/json_writer.h"

namespace ndtom::mapper {

uint64_t budgetForInput(uint64_t input_bytes, uint64_t available_bytes, uint64_t floor) {
  const uint64_t scaled = input_bytes > UINT64_MAX / kBudgetPerInputByte
                              ? UINT64_MAX
                              : input_bytes * kBudgetPerInputByte;
  uint64_t budget = std::max(scaled, floor);
  if (available_bytes > 0) budget = std::min(budget, std::max(floor, available_bytes / 2));
  return budget;
}

uint64_t inputBytes(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::is_regular_file(path, error)) {
    const uintmax_t size = fs::file_size(path, error);
    return error ? 0 : uint64_t(size);
  }
  uint64_t total = 0;
  fs::recursive_directory_iterator it(path, fs::directory_options::skip_permission_denied, error);
  for (; !error && it != fs::recursive_directory_iterator(); it.increment(error)) {
    std::error_code entry_error;
    if (it->is_regular_file(entry_error)) {
      const uintmax_t size = it->file_size(entry_error);
      if (!entry_error) total += uint64_t(size);
    }
  }
  return total;
}

uint64_t availableMemoryBytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string line;
  while (std::getline(meminfo, line)) {
    unsigned long long kb = 0;
    if (std::sscanf(line.c_str(), "MemAvailable: %llu kB", &kb) == 1) return uint64_t(kb) * 1024;
  }
  return 0;
}

namespace {

std::string megabytesText(uint64_t bytes) {
  char text[32];
  if (bytes >= 10000000000ULL)
    std::snprintf(text, sizeof text, "%.1f GB", double(bytes) / 1e9);
  else if (bytes < 10000000)
    std::snprintf(text, sizeof text, "%.2g MB", double(bytes) / 1e6);
  else
    std::snprintf(text, sizeof text, "%.0f MB", double(bytes) / 1e6);
  return text;
}

}  // namespace

RunBudget applyRunBudget(InsertionOptions& options, const InsertionSettings& settings,
                         const std::string& input) {
  RunBudget budget;
  budget.given = std::any_of(settings.overrides.begin(), settings.overrides.end(),
                             [](const auto& o) { return o.first == "memory_budget"; });
  if (budget.given) {
    budget.bytes = options.scan.memory_budget;
    budget.rule = "--memory-budget";
    return budget;
  }
  budget.input_bytes = inputBytes(input);
  budget.available_bytes = availableMemoryBytes();
  budget.bytes = budgetForInput(budget.input_bytes, budget.available_bytes, defaultMemoryBudget());
  options.scan.memory_budget = budget.bytes;
  std::ostringstream rule;
  rule << kBudgetPerInputByte << " x the input's " << megabytesText(budget.input_bytes)
       << ", at least " << megabytesText(defaultMemoryBudget());
  if (budget.available_bytes > 0)
    rule << ", at most half of the " << megabytesText(budget.available_bytes) << " available";
  budget.rule = rule.str();
  return budget;
}

bool needsOutOfCore(const RunBudget& budget) {
  return !budget.given && budget.available_bytes > 0 &&
         budget.input_bytes > budget.available_bytes / 2 / kBudgetPerInputByte;
}

void writeRunBudget(apps::JsonWriter& json, const RunBudget& budget) {
  json.field("budget_bytes", budget.bytes);
  json.field("budget_rule", budget.rule);
  json.field("input_bytes", budget.input_bytes);
  json.field("available_bytes", budget.available_bytes);
}

}  // namespace ndtom::mapper
