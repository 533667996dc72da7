// The account of a run: what was read, what the map holds, time and memory, the files
// written. As JSON (PREFIX.summary.json) and as a short text for the terminal.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "map_builder.h"
#include "ndtom_apps/map_outputs.h"
#include "ndtom_apps/output_files.h"
#include "ndtom_apps/run_budget.h"
#include "ndtom_apps/stage_times.h"

namespace ndtom::mapper {

/// An out-of-core build: its settings and what OutOfCoreMap counted.
struct OutOfCoreInfo {
  uint64_t resident_budget = 0;  ///< bytes
  int tile_blocks = 0;
  ndtom::OutOfCoreMap::Stats stats;
};

struct RunSummary {
  std::string input, format;
  ndtom::MapOptions map_options;
  int threads = 1;
  const MappingResult* mapping = nullptr;
  std::optional<CoarseMapInfo> coarse;
  std::optional<OutOfCoreInfo> out_of_core;
  RunBudget budget;  ///< the map's memory budget and why
  double total_seconds = 0;
  size_t peak_rss_after_mapping = 0;  ///< bytes, before the pictures and files
  size_t peak_rss = 0;                ///< bytes, whole run
  std::vector<apps::WrittenFile> files;
  const apps::StageTimes* stages = nullptr;  ///< reading, inserting, each output
};

/// Largest |x_pass - x_first| / x_first over the passes, in percent, for cells and map bytes.
struct PassDrift {
  double cells_percent = 0, map_bytes_percent = 0;
};
PassDrift passDrift(const std::vector<PassResult>& passes);

std::string summaryJson(const RunSummary& summary);
std::string summaryText(const RunSummary& summary);

}  // namespace ndtom::mapper
