#include "slam_options.h"

#include <mrpt/config/CConfigFile.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include "mrpt_ndtom/CMetricMapBuilderNDT.h"
#include "ndtom_apps/command_line.h"
#include "ndtom_apps/input_format.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_apps/run_program.h"

namespace ndtom::slam {
namespace {

using apps::parseInteger;
using apps::parseOnOff;
using apps::parseReal;
using apps::UsageError;

const apps::OptionTable<SlamOptions>& optionTable() {
  using O = SlamOptions;
  static const apps::OptionTable<O> table = {
      {"--method",
       {true,
        [](O& o, const std::string& v) {
          try {
            o.online.placement.registration.method = ndtom::registrationMethodFromString(v);
          } catch (const std::invalid_argument&) {
            throw UsageError("--method: expected p2d or d2d, got '" + v + "'");
          }
        }}},
      {"--levels",
       {true, [](O& o, const std::string& v) { o.online.placement.registration.level_factors = apps::parseLevelFactors("--levels", v); }}},
      {"--planar", {false, [](O& o, const std::string&) { o.online.placement.registration.planar = true; }}},
      {"--max-points",
       {true,
        [](O& o, const std::string& v) {
          o.online.placement.registration.max_points = size_t(parseInteger("--max-points", v, 10, 100000000));
        }}},
      {"--target-radius",
       {true, [](O& o, const std::string& v) { o.online.target_radius = parseReal("--target-radius", v); }}},
      {"--target-refresh",
       {true,
        [](O& o, const std::string& v) {
          o.online.target_refresh_distance = parseReal("--target-refresh", v);
        }}},
      {"--free-space-overrule",
       {true,
        [](O& o, const std::string& v) {
          o.online.free_space_overrule = parseReal("--free-space-overrule", v);
        }}},
      {"--recovery-radius",
       {true, [](O& o, const std::string& v) { o.online.placement.recovery_radius = parseReal("--recovery-radius", v); }}},
      {"--recovery-yaw",
       {true, [](O& o, const std::string& v) { o.online.placement.recovery_yaw_deg = parseReal("--recovery-yaw", v); }}},
      {"--ground-thinning",
       {true,
        [](O& o, const std::string& v) {
          o.online.placement.ground_thinning = int(parseInteger("--ground-thinning", v, 1, 1000));
        }}},
      {"--weak-sigma",
       {true,
        [](O& o, const std::string& v) { o.online.placement.weak_direction_sigma = parseReal("--weak-sigma", v); }}},
      {"--retry-without-finest",
       {true,
        [](O& o, const std::string& v) {
          o.online.placement.retry_without_finest = parseOnOff("--retry-without-finest", v);
        }}},
      {"--min-judged-fraction",
       {true,
        [](O& o, const std::string& v) {
          o.online.placement.registration.min_judged_fraction = parseReal("--min-judged-fraction", v);
        }}},
      {"--min-matched-fraction",
       {true,
        [](O& o, const std::string& v) {
          o.online.placement.registration.min_matched_fraction = parseReal("--min-matched-fraction", v);
        }}},
      {"--loop-closure",
       {true,
        [](O& o, const std::string& v) { o.loops.enabled = parseOnOff("--loop-closure", v); }}},
      {"--keyframe-distance",
       {true,
        [](O& o, const std::string& v) {
          o.loops.keyframes.distance = parseReal("--keyframe-distance", v);
        }}},
      {"--loop-radius",
       {true,
        [](O& o, const std::string& v) {
          o.loops.search.base_radius = parseReal("--loop-radius", v);
        }}},
      {"--loop-drift",
       {true,
        [](O& o, const std::string& v) {
          o.loops.search.drift_per_metre = parseReal("--loop-drift", v);
        }}},
      {"--loop-local-radius",
       {true,
        [](O& o, const std::string& v) {
          o.loops.search.max_local_radius = parseReal("--loop-local-radius", v);
        }}},
      {"--reference", {true, [](O& o, const std::string& v) { o.reference_file = v; }}},
  };
  return table;
}

// ndtom-map's options that give poses or replay the input: ndtom-slam finds the poses itself.
const std::set<std::string>& refusedMapOptions() {
  static const std::set<std::string> refused = {"--poses", "--pose-format", "--pose-time-tolerance",
                                                "--passes", "--resident-budget", "--spill-dir",
                                                "--min-travel", "--min-turn"};
  return refused;
}

// --config FILE.ini: CMetricMapBuilderNDT's sections (share/mrpt/ndtom-slam.ini), the online
// mapper's keys from [--section] and the map's from [<section>_ndtOccupancyMap_00_insertOpts]
// through ndtom-map's own --config. Read before the flags, which override it.
struct ConfigFile {
  std::string path;  ///< empty: none
  std::string section = kDefaultSlamSection;
};

// The value of `name` ("--name v" or "--name=v") among the arguments; the last one wins.
std::string argumentValue(int argc, char** argv, const std::string& name, std::string value) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == name && i + 1 < argc)
      value = argv[++i];
    else if (arg.rfind(name + "=", 0) == 0)
      value = arg.substr(name.size() + 1);
  }
  return value;
}

// The online mapper's options from the file's section; every key one the builder saves.
ndtom::OnlineMapperOptions loadOnline(const ConfigFile& config,
                                      const mrpt::config::CConfigFile& file) {
  using Params = mrpt_ndtom::CMetricMapBuilderNDT::TConfigParams;
  const std::vector<std::string> known = Params::keys();
  std::vector<std::string> keys;
  file.getAllKeys(config.section, keys);
  for (std::string key : keys) {
    key = apps::trim(key);
    if (std::find(known.begin(), known.end(), key) == known.end())
      throw UsageError(config.path + ": [" + config.section + "] unknown key '" + key + "'");
  }
  Params params;
  try {
    params.loadFromConfigFile(file, config.section);
  } catch (const std::exception& e) {
    throw UsageError(config.path + ": " + apps::oneLineMessage(e));
  }
  return params.online;
}

// Applies the file to `o` and says whether it has the map's section.
bool applyConfig(const ConfigFile& config, SlamOptions& o) {
  apps::requireRegularFile("--config", config.path);  // MRPT's reader would wait on a FIFO
  if (!std::ifstream(config.path).good())
    throw UsageError("--config " + config.path + ": cannot open the file");
  const mrpt::config::CConfigFile file(config.path);
  const std::string map_section =
      mrpt_ndtom::CMetricMapBuilderNDT::TConfigParams::mapSection(config.section);
  const bool has_map = file.sectionExists(map_section);
  if (!file.sectionExists(config.section) && !has_map)
    throw UsageError(config.path + ": no section [" + config.section +
                     "] (choose one with --section)");
  if (file.sectionExists(config.section)) o.online = loadOnline(config, file);
  return has_map;
}

}  // namespace

SlamOptions parseSlamOptions(int argc, char** argv) {
  SlamOptions o;
  const auto& table = optionTable();
  // The file first, then the flags given, which override it.
  ConfigFile config;
  config.path = argumentValue(argc, argv, "--config", "");
  config.section = argumentValue(argc, argv, "--section", config.section);
  const bool help = std::any_of(argv + 1, argv + argc, [](const char* a) {
    return std::string(a) == "--help" || std::string(a) == "-h";
  });
  const bool config_has_map = !config.path.empty() && !help && applyConfig(config, o);
  // Ours first; everything else is ndtom-map's, parsed by its own parser.
  std::vector<std::string> rest = {argv[0]};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const size_t eq = arg.rfind("--", 0) == 0 ? arg.find('=') : std::string::npos;
    const std::string name = arg.substr(0, eq);
    if (refusedMapOptions().count(name))
      throw UsageError(name +
                       ": ndtom-slam finds the poses itself (use ndtom-map for given poses)");
    if (name == "--help" || name == "-h") o.help = true;
    if (name == "--config" || name == "--section") {  // read above
      if (eq == std::string::npos && ++i >= argc)
        throw UsageError(name + ": missing value (see --help)");
      continue;
    }
    const auto spec = table.find(name);
    if (spec == table.end()) {
      rest.push_back(arg);
      continue;
    }
    std::string value;
    if (eq != std::string::npos) {
      value = arg.substr(eq + 1);
    } else if (spec->second.takes_value) {
      if (i + 1 >= argc) throw UsageError(name + ": missing value (see --help)");
      value = argv[++i];
    }
    spec->second.handle(o, value);
  }
  if (o.help) return o;
  // The map's keys: ndtom-map's --config reads them, under its own flags.
  if (config_has_map)
    rest.insert(rest.end(),
                {"--config", config.path, "--section",
                 mrpt_ndtom::CMetricMapBuilderNDT::TConfigParams::mapSection(config.section)});
  std::vector<char*> rest_argv;
  for (std::string& a : rest) rest_argv.push_back(a.data());
  o.map = mapper::parseMapperOptions(int(rest_argv.size()), rest_argv.data());
  std::error_code ec;
  if (!o.reference_file.empty() && !std::filesystem::is_regular_file(o.reference_file, ec))
    throw UsageError("--reference " + o.reference_file + ": no such file");
  try {
    OnlineMapperOptions check = o.online;
    check.map = ndtom::MapOptions{};
    ndtom::validate(check);
    validate(o.loops);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  return o;
}

std::string helpText() {
  std::ostringstream s;
  s << "ndtom-slam: maps a log without given poses. Each scan is registered against the NDT-OM\n"
       "built so far (coarse to fine, from a constant-velocity or odometry prediction), then\n"
       "inserted at the pose found: the paper's online mapping, as lidar odometry.\n"
       "\n"
       "Usage: ndtom-slam INPUT -o PREFIX [options]\n"
       "\n"
       "INPUT, the map's options (--resolution, ...) and the outputs are ndtom-map's (see\n"
       "ndtom-map --help), without the options that give poses (--poses, --passes, ...):\n"
       "a PCD folder's poses.txt is not read; a rawlog's odometry is the prediction.\n"
       "The memory budget, unless --memory-budget is given, is ndtom-map's: 4 x the input's\n"
       "size on disk, at least 512 MB, at most half the memory available.\n"
       "It writes what ndtom-map writes, plus PREFIX.tum (one line per scan: time, position,\n"
       "quaternion, the sensor's pose for PCD scans, the robot's for rawlogs) from which\n"
       "ndtom-map INPUT --poses PREFIX.tum rebuilds the same map bit for bit.\n"
       "\n"
       "Configuration file (the flags given override it):\n"
       "  --config FILE.ini         as share/mrpt/ndtom-slam.ini: registration and recovery\n"
       "                            keys from [SECTION], the map's from\n"
       "                            [SECTION_ndtOccupancyMap_00_insertOpts] (threads: the map's)\n"
       "  --section NAME            SECTION ("
    << kDefaultSlamSection
    << ")\n"
       "\n"
       "Registration:\n"
       "  --method p2d|d2d          point-to-distribution or distribution-to-distribution (p2d)\n"
       "  --levels LIST             pyramid, coarse to fine, multiples of the cell (16,8,4,2)\n"
       "  --planar                  only x, y, yaw (2D scans, flat ground)\n"
       "  --max-points N            scan points per level at most (6000)\n"
       "  --min-matched-fraction F  verdict: matched part of what the map can judge (0.25)\n"
       "  --min-judged-fraction F   verdict: scan share where the map has looked (0.15)\n"
       "  --target-radius M         register against the map within M metres (50)\n"
       "  --target-refresh M        move that region with the sensor every M metres (2; 0: every\n"
       "                            scan); it follows the map at every scan\n"
       "  --recovery-radius M       when the verdict fails: search x, y within M metres (2)\n"
       "  --recovery-yaw DEG        ... and yaw within +-DEG of the prediction (60)\n"
       "  --ground-thinning K       one in K points on the scan's ground plane registers (100);\n"
       "                            all are inserted. On flat ground every ring point makes a\n"
       "                            moving lidar seem to stand still\n"
       "  --retry-without-finest on|off  a scan the whole pyramid cannot place is tried\n"
       "                            without its finest level (on): a sparse lidar's second\n"
       "                            scan against the first one's map\n"
       "  --weak-sigma M            directions the scene constrains worse than M (std. dev.)\n"
       "                            keep the prediction (0.1)\n"
       "  --free-space-overrule M   a scan only the free-space check refuses is placed if its\n"
       "                            registration ends within M metres (and half the predicted\n"
       "                            step) and 1 degree of the prediction (0.1; 0: never): rays\n"
       "                            that grazed a wall, or drift, made the map's free space\n"
       "                            wrong there\n"
       "  --threads N               threads of registration and insertion: the map's\n"
       "                            --threads key (same result for any count)\n"
       "\n"
       "Loop closure (keyframes, a pose graph optimized by MRPT's mrpt-graphslam):\n"
       "  --loop-closure on|off     off: odometry only, the live map holds every scan (off;\n"
       "                            on: keyframes, loop closure, MRPT's graph optimizer)\n"
       "  --keyframe-distance M     a keyframe every M metres or 30 degrees of turn (10)\n"
       "  --loop-radius M           loop candidates within M metres of the graph's pose ...\n"
       "  --loop-drift F            ... plus F times the path since the last closure (2, 0.01)\n"
       "  --loop-local-radius M     past this radius the old submap is searched whole (6)\n"
       "\n"
       "Evaluation:\n"
       "  --reference FILE          trajectory to compare with (TUM or KITTI, pose i = scan i):\n"
       "                            ATE after alignment and final drift in the summary\n"
       "  -q, --quiet               no progress, no summary on stdout\n"
       "  -h, --help                this text\n"
       "\n"
       "Example: ndtom-slam tests/data/balm-realworld -o out/slam --resolution 0.2\n";
  return s.str();
}

}  // namespace ndtom::slam
