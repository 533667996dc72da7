#include "insertion_settings.h"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <limits>
#include <thread>

#include "input_format.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_apps/run_program.h"

namespace ndtom::mapper {
namespace {

using apps::oneLineMessage;
using apps::parseBool;
using apps::parseInteger;
using apps::parseReal;
using apps::trim;
using apps::UsageError;

// Parses `text` for the key and stores it; `option` names the value's origin in errors.
using Setter =
    std::function<void(InsertionOptions&, const std::string& option, const std::string& text)>;

struct KeySpec {
  InsertionKey key;
  Setter set;
};

Setter real(double InsertionOptions::*field, bool allow_infinity = false) {
  return [=](InsertionOptions& o, const std::string& option, const std::string& text) {
    o.*field = parseReal(option, text, allow_infinity);
  };
}

Setter count(uint32_t InsertionOptions::*field) {
  return [=](InsertionOptions& o, const std::string& option, const std::string& text) {
    o.*field = uint32_t(parseInteger(option, text, 1, std::numeric_limits<int32_t>::max()));
  };
}

void setRayMode(InsertionOptions& o, const std::string& option, const std::string& text) {
  // The spellings MRPT's read_enum and the core both understand.
  if (text == "PerPoint" || text == "0")
    o.ray_mode = ndtom::RayMode::PerPoint;
  else if (text == "PerHitCell" || text == "1")
    o.ray_mode = ndtom::RayMode::PerHitCell;
  else
    throw UsageError(option + ": expected PerPoint or PerHitCell, got '" + text + "'");
}

const std::vector<KeySpec>& keySpecs() {
  using O = InsertionOptions;
  static const std::vector<KeySpec> specs = {
      {{"resolution", "cell edge [m] (0.2)"}, real(&O::resolution)},
      {{"occupancy_enabled", "ray tracing, Eq. 12; false: Recursive NDT (true)"},
       [](O& o, const std::string& option, const std::string& text) {
         o.occupancy_enabled = parseBool(option, text);
       }},
      {{"p_hit", "p_o, occupancy of a cell with hits (0.6)"}, real(&O::p_hit)},
      {{"p_miss", "p_e, occupancy of a cell a ray crosses (0.49)"}, real(&O::p_miss)},
      {{"logodds_min", "lower log-odds clamp (-2)"}, real(&O::logodds_min)},
      {{"logodds_max", "upper log-odds clamp (3.5)"}, real(&O::logodds_max)},
      {{"min_range", "closer points are dropped [m] (0)"}, real(&O::min_range)},
      {{"max_range", "farther points: free ray to here, no hit [m] (100)"},
       real(&O::max_range, /*allow_infinity=*/true)},
      {{"ray_mode", "PerPoint or PerHitCell (PerPoint)"}, setRayMode},
      {{"decimation", "keep 1 point in N of scans and clouds (1)"}, count(&O::decimation)},
      {{"decimation_3d_range", "depth images: every N-th row and column (1)"},
       count(&O::decimation_3d_range)},
      {{"min_eigen_ratio", "covariance eigenvalue floor / largest (0.01)"},
       real(&O::min_eigen_ratio)},
      {{"min_eigen_abs", "covariance eigenvalue floor [m^2] (1e-6)"}, real(&O::min_eigen_abs)},
      {{"threads", "threads inserting a scan; the same map for any count (the\n" +
                       std::string(28, ' ') + "machine's cores)"},
       [](O& o, const std::string& option, const std::string& text) {
         o.threads = int32_t(parseInteger(option, text, 1, 256));
       }},
      {{"memory_budget", "MB the map and a scan may take; larger scans stop the run\n" +
                             std::string(28, ' ') + "(a quarter of the RAM, at most 512)"},
       real(&O::memory_budget)},
  };
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
    // A strict parse on a scratch copy: the plugin's loader would read "abc" as 0.
    InsertionOptions scratch;
    if (const KeySpec* spec = findSpec(key))
      spec->set(scratch, path + ": [" + section + "] " + key,
                trim(file.read_string(section, key, "")));
  }
}

// The plugin's defaults, but as many threads as the machine has cores: the map is the same
// for any count, so a program has no reason to leave cores idle.
InsertionOptions programDefaults() {
  InsertionOptions o;
  o.threads = std::clamp(int32_t(std::thread::hardware_concurrency()), int32_t(1),
                         int32_t(ndtom::InsertOptions::kMaxThreads));
  return o;
}

InsertionOptions loadFile(const InsertionSettings& s) {
  InsertionOptions options = programDefaults();
  requireRegularFile("--config", s.config_file);  // MRPT's reader would wait on a FIFO
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
