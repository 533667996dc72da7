#include "ndtom_apps/insertion_settings.h"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <functional>
#include <thread>

#include "ndtom/map/option_table.h"
#include "ndtom/map/option_text.h"
#include "ndtom_apps/input_format.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_apps/run_program.h"

namespace ndtom::mapper {
namespace {

using apps::oneLineMessage;
using apps::parseInteger;
using apps::trim;
using apps::UsageError;

// Parses `text` for the key and stores it; `option` names the value's origin in errors.
using Setter =
    std::function<void(InsertionOptions&, const std::string& option, const std::string& text)>;

struct KeySpec {
  InsertionKey key;
  Setter set;
};

Setter count(uint32_t InsertionOptions::*field) {
  return [=](InsertionOptions& o, const std::string& option, const std::string& text) {
    o.*field = uint32_t(
        parseInteger(option, text, 1, mrpt_ndtom::TPointExtractionOptions::kMaxDecimation));
  };
}

// A value of the core's option table, parsed as the row's type by the reader the plugin's
// .ini sections use, and checked at once.
Setter rowSetter(const ndtom::OptionRow& row) {
  return [&row](InsertionOptions& o, const std::string& option, const std::string& text) {
    double value = 0;
    try {
      value = ndtom::optionFromText(row, option, text);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
    try {
      ndtom::checkOptionValue(row, value);
    } catch (const std::invalid_argument& e) {  // names the row: "p_hit = 2: ..."
      throw UsageError(option + ": " + e.what());
    }
    row.set(o, value);
  };
}

// "description [unit] (default)", wrapped to the --help column.
std::string helpOf(const ndtom::OptionRow& row, const InsertionOptions& defaults) {
  std::string text = row.description;
  text[0] = char(std::tolower(static_cast<unsigned char>(text[0])));
  if (*row.unit) text += std::string(" [") + row.unit + "]";
  const std::string value = ndtom::optionValueText(row, row.get(defaults));
  text += row.scope == ndtom::OptionScope::Machine ? " (this machine: " + value + ")"
                                                   : " (" + value + ")";
  constexpr size_t kWidth = 62;  // 90 columns less the 28 of the option names
  for (size_t line_start = 0; text.size() - line_start > kWidth;) {
    const size_t cut = text.rfind(' ', line_start + kWidth);
    if (cut == std::string::npos || cut <= line_start) break;
    text.replace(cut, 1, "\n" + std::string(28, ' '));
    line_start = cut + 1 + 28;
  }
  return text;
}

InsertionOptions programDefaults();

const std::vector<KeySpec>& keySpecs() {
  static const std::vector<KeySpec> specs = [] {
    const InsertionOptions defaults = programDefaults();
    std::vector<KeySpec> k;
    for (const ndtom::OptionRow& row : ndtom::kMapOptionRows)
      k.push_back({{row.name, helpOf(row, defaults)}, rowSetter(row)});
    // The plugin's own: how points are taken from observations.
    k.push_back({{"decimation", "keep 1 point in N of scans and clouds (1)"},
                 count(&InsertionOptions::decimation)});
    k.push_back({{"decimation_3d_range", "depth images: every N-th row and column (1)"},
                 count(&InsertionOptions::decimation_3d_range)});
    return k;
  }();
  return specs;
}

const KeySpec* findSpec(const std::string& name) {
  for (const auto& s : keySpecs())
    if (s.key.name == name) return &s;
  return nullptr;
}

// The keys the plugin itself saves: a key it does not know is a typo, not an option.
std::vector<std::string> pluginKeys() {
  mrpt::config::CConfigFileMemory memory;
  InsertionOptions().saveToConfigFile(memory, "s");
  std::vector<std::string> keys;
  memory.getAllKeys("s", keys);
  for (auto& key : keys) key = trim(key);  // MRPT pads saved keys to a column
  return keys;
}

void checkSection(const mrpt::config::CConfigFileBase& file, const std::string& path,
                  const std::string& section) {
  if (!file.sectionExists(section))
    throw UsageError(path + ": no section [" + section + "] (choose one with --section)");
  std::vector<std::string> keys;
  file.getAllKeys(section, keys);
  const std::vector<std::string> known = pluginKeys();
  for (std::string key : keys) {
    key = trim(key);
    if (std::find(known.begin(), known.end(), key) == known.end())
      throw UsageError(path + ": [" + section + "] unknown key '" + key + "'");
  }
}

// The plugin's defaults, but as many threads as the machine has cores: the map is the same
// for any count, so a program has no reason to leave cores idle.
InsertionOptions programDefaults() {
  InsertionOptions o;
  o.scan.threads = std::clamp(int32_t(std::thread::hardware_concurrency()), int32_t(1),
                              int32_t(ndtom::ScanOptions::kMaxThreads));
  return o;
}

InsertionOptions loadFile(const InsertionSettings& s) {
  InsertionOptions options = programDefaults();
  apps::requireRegularFile("--config", s.config_file);  // MRPT's reader would wait on a FIFO
  if (!std::ifstream(s.config_file).good())
    throw UsageError("--config " + s.config_file + ": cannot open the file");
  const mrpt::config::CConfigFile file(s.config_file);
  checkSection(file, s.config_file, s.section);
  try {
    options.loadFromConfigFile(file, s.section);
  } catch (const std::exception& e) {
    throw UsageError(s.config_file + ": " + oneLineMessage(e));
  }
  return options;
}

}  // namespace

const std::vector<InsertionKey>& insertionKeys() {
  static const std::vector<InsertionKey> keys = [] {
    std::vector<InsertionKey> k;
    for (const auto& s : keySpecs()) k.push_back(s.key);
    return k;
  }();
  return keys;
}

bool isInsertionKey(const std::string& name) {
  return findSpec(name) != nullptr;
}

InsertionOptions resolveInsertionOptions(const InsertionSettings& settings) {
  InsertionOptions options = settings.config_file.empty() ? programDefaults() : loadFile(settings);
  for (const auto& [key, text] : settings.overrides) {
    const KeySpec* spec = findSpec(key);
    std::string option = "--" + key;
    std::replace(option.begin(), option.end(), '_', '-');
    if (!spec) throw UsageError(option + ": unknown option (see --help)");
    spec->set(options, option, text);
  }
  try {
    options.toMapOptions();  // validates every value together (e.g. max_range > min_range)
  } catch (const std::exception& e) {
    throw UsageError(std::string("insertion options: ") + e.what());
  }
  return options;
}

}  // namespace ndtom::mapper
