// The map's insertion options, under the plugin's .ini keys (resolution, p_hit, ...): from a
// section of an MRPT .ini file, then from the command line, which overrides the file.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "mrpt_ndtom/CNDTOccupancyMap.h"

namespace ndtom::mapper {

using InsertionOptions = mrpt_ndtom::CNDTOccupancyMap::TInsertionOptions;

/// The default section: the one CMultiMetricMap reads for the first ndtOccupancyMap.
inline const std::string kDefaultInsertionSection = "MetricMap_ndtOccupancyMap_00_insertOpts";

struct InsertionKey {
  std::string name;  ///< as in the .ini file, e.g. "p_hit"; on the command line "--p-hit"
  std::string help;
};
/// Every option of TInsertionOptions, in the order --help lists them.
const std::vector<InsertionKey>& insertionKeys();
bool isInsertionKey(const std::string& name);

struct InsertionSettings {
  std::string config_file;  ///< empty: no file
  std::string section = kDefaultInsertionSection;
  /// (.ini key, value text) from the command line, applied in order after the file.
  std::vector<std::pair<std::string, std::string>> overrides;
};

/// Defaults, then the file's section (no key the plugin does not save; the values read by
/// TInsertionOptions::loadFromConfigFile, whose reader the overrides share), then the
/// overrides; the result is validated.
/// Throws apps::UsageError with a one-line message naming the file, key or option.
InsertionOptions resolveInsertionOptions(const InsertionSettings& settings);

}  // namespace ndtom::mapper
