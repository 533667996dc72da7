// The memory budget of a mapping run (ndtom-map, ndtom-slam) when --memory-budget is not
// given: it grows with the input, so that a campus or a city drive maps with default options
// on a machine with room to spare, while a small file (a hostile one included) keeps the
// library's default and cannot make a run take gigabytes.
#pragma once

#include <cstdint>
#include <string>

#include "ndtom_apps/insertion_settings.h"

namespace ndtom::apps {
class JsonWriter;
}

namespace ndtom::mapper {

/// A map of lidar scans takes about their bytes on disk (1 km of ndtom-worldgen's city: 287
/// MB of PCD files, a 245 MB map at 0.2 m); a run holds its scan buffers and registration
/// pyramid beside it.
inline constexpr uint64_t kBudgetPerInputByte = 4;

struct RunBudget {
  uint64_t bytes = 0;            ///< the budget
  uint64_t input_bytes = 0;      ///< the input's size on disk
  uint64_t available_bytes = 0;  ///< the machine's memory available at the start (0: unknown)
  bool given = false;            ///< --memory-budget was given: the rule did not apply
  /// For the summary, e.g. "4 x the input's 287 MB, at most half of the 22.6 GB available".
  std::string rule;
};

/// kBudgetPerInputByte × `input_bytes`, at least `floor` (the library's default) and at most
/// half of `available_bytes` (unless that is below `floor`; 0: unknown, no upper limit).
uint64_t budgetForInput(uint64_t input_bytes, uint64_t available_bytes, uint64_t floor);

/// Bytes of the file, or of the regular files under the folder (recursively), at `path`; 0 if
/// it cannot be read (the run's own reader then says why).
uint64_t inputBytes(const std::string& path);

/// The memory the machine has available now (/proc/meminfo's MemAvailable); 0 if unknown.
uint64_t availableMemoryBytes();

/// Sets `options.scan.memory_budget` by budgetForInput() unless the command line gave
/// memory_budget (`settings.overrides`), and says which.
RunBudget applyRunBudget(InsertionOptions& options, const InsertionSettings& settings,
                         const std::string& input);

/// Whether a run under `budget` should build out of core by itself: the rule's budget was
/// capped by the memory available (4 x the input does not fit in half of it), so the map,
/// about the input's size, and the outputs made from it in memory may not fit either.
bool needsOutOfCore(const RunBudget& budget);

/// The budget's fields in a summary's current JSON object: budget_bytes, budget_rule,
/// input_bytes, available_bytes.
void writeRunBudget(apps::JsonWriter& json, const RunBudget& budget);

}  // namespace ndtom::mapper
