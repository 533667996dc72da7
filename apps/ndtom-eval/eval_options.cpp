#include "eval_options.h"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>

#include "ndtom_apps/option_values.h"

namespace ndtom::eval {

namespace {

// The shared datasets beside the source tree the program was built in; once installed (and
// without them), <prefix>/share/ndtom/data, which holds the TUM demo frames, found from the
// executable's own path so that a moved or unpacked prefix works too.
std::string defaultDataDir() {
  namespace fs = std::filesystem;
  const std::string shared = std::string(NDTOM_SOURCE_DIR) + "/../shared/datasets";
  std::error_code error;
  if (fs::is_directory(shared, error)) return shared;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (error) return shared;
  const fs::path installed = exe.parent_path().parent_path() / NDTOM_INSTALL_DATADIR / "ndtom/data";
  return fs::is_directory(installed, error) ? installed.string() : shared;
}

int parseCount(const std::string& option, const std::string& text, int min_value) {
  return int(apps::parseInteger(option, text, min_value, 1000000));
}

double parsePositive(const std::string& option, const std::string& text) {
  const double v = apps::parseReal(option, text);
  if (!(v > 0)) throw apps::UsageError(option + ": must be > 0");
  return v;
}

double parseResolution(const std::string& option, const std::string& text) {
  const double v = apps::parseReal(option, text);
  if (!(v >= 0.01 && v <= 10.0))
    throw apps::UsageError(option + ": resolution must be in [0.01, 10] m");
  return v;
}

std::vector<double> parseResolutions(const std::string& option, const std::string& text) {
  std::vector<double> values;
  for (const std::string& item : apps::splitList(text))
    values.push_back(parseResolution(option, item));
  if (values.empty()) throw apps::UsageError(option + ": empty list");
  return values;
}

/// A non-empty subset of `allowed`.
std::set<std::string> parseChoice(const std::string& option, const std::string& text,
                                  const std::vector<std::string>& allowed) {
  std::set<std::string> chosen;
  for (const std::string& name : apps::splitList(text)) {
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
      throw apps::UsageError(option + ": unknown name '" + name + "' (see --help)");
    chosen.insert(name);
  }
  if (chosen.empty()) throw apps::UsageError(option + ": empty list");
  return chosen;
}

}  // namespace

EvalOptions parseEvalOptions(int argc, char** argv) {
  EvalOptions o;
  const std::string data = defaultDataDir();
  o.tum_dir = data + "/tum-fr2-pioneer-slam2";
  o.lidar_dir = data + "/balm-realworld";
  using Setter = std::function<void(const std::string& option, const std::string& value)>;
  const std::map<std::string, Setter> setters = {
      {"--tum", [&](auto&, auto& v) { o.tum_dir = v; }},
      {"--lidar", [&](auto&, auto& v) { o.lidar_dir = v; }},
      {"--out", [&](auto&, auto& v) { o.out_dir = v; }},
      {"--tum-frames", [&](auto& a, auto& v) { o.tum_frames = parseCount(a, v, 1); }},
      {"--tum-decimation", [&](auto& a, auto& v) { o.tum_decimation = parseCount(a, v, 1); }},
      {"--lidar-scans", [&](auto& a, auto& v) { o.lidar_scans = parseCount(a, v, 1); }},
      {"--consistency-scans", [&](auto& a, auto& v) { o.consistency_scans = parseCount(a, v, 1); }},
      {"--tum-resolution", [&](auto& a, auto& v) { o.tum_resolution = parseResolution(a, v); }},
      {"--lidar-resolution", [&](auto& a, auto& v) { o.lidar_resolution = parseResolution(a, v); }},
      {"--mapping-resolution",
       [&](auto& a, auto& v) { o.mapping_resolution = parseResolution(a, v); }},
      {"--coarsening", [&](auto& a, auto& v) { o.coarsening = parseCount(a, v, 2); }},
      {"--sweep", [&](auto& a, auto& v) { o.sweep_resolutions = parseResolutions(a, v); }},
      {"--ray-mode-resolutions",
       [&](auto& a, auto& v) { o.ray_mode_resolutions = parseResolutions(a, v); }},
      {"--min-eigenvalue", [&](auto& a, auto& v) { o.min_eigenvalue = parsePositive(a, v); }},
      {"--clamp-min", [&](auto& a, auto& v) { o.clamp_min = apps::parseReal(a, v); }},
      {"--clamp-max", [&](auto& a, auto& v) { o.clamp_max = apps::parseReal(a, v); }},
      {"--min-travel", [&](auto& a, auto& v) { o.motion.min_travel = parsePositive(a, v); }},
      {"--min-turn", [&](auto& a, auto& v) { o.motion.min_turn_deg = parsePositive(a, v); }},
      {"--experiments",
       [&](auto& a, auto& v) { o.experiments = parseChoice(a, v, kExperimentNames); }},
      {"--consistency-data",
       [&](auto& a, auto& v) {
         o.consistency_data = parseChoice(a, v, {"tum", "lidar"});
       }},
  };
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      o.help = true;
      continue;
    }
    const auto setter = setters.find(arg);
    if (setter == setters.end()) throw apps::UsageError(arg + ": unknown option (see --help)");
    if (i + 1 >= argc) throw apps::UsageError(arg + ": missing value");
    setter->second(arg, argv[++i]);
  }
  if (!(o.clamp_min < 0 && o.clamp_max > 0))
    throw apps::UsageError("--clamp-min/--clamp-max: need clamp-min < 0 < clamp-max");
  if (o.motion.min_turn_deg > 180) throw apps::UsageError("--min-turn: must be <= 180 degrees");
  return o;
}

std::string helpText() {
  return R"(ndtom-eval: reproduces the evaluation of Saarinen et al. 2013 (Sec. IV) on real data.

Usage: ndtom-eval [options]

Data (defaults: ../shared/datasets beside the repository; installed: share/ndtom/data):
  --tum DIR                  TUM RGB-D sequence (associations.txt with poses, depth/*.png)
  --lidar DIR                lidar scans fullN.pcd + poses.txt (KITTI, sensor -> world)
  --out DIR                  output folder for CSV and PNG files (default: ndtom-eval-out)
  --tum-frames N             use the first N TUM frames (default: all)
  --tum-decimation K         use every K-th depth pixel in both directions (default: 1)
  --lidar-scans N            lidar scans for mapping, multires, sweep, raymodes (default: all)
  --consistency-scans N      lidar scans for Fig. 1 and 2 (default: 30)
  --consistency-data LIST    datasets for Fig. 1 and 2: tum,lidar (default: both)
  --min-travel M             the paper's insertion rule on the lidar scans: keep a scan only
  --min-turn DEG             if the sensor moved >= M m or turned >= DEG degrees since the
                             last kept one (paper: 0.05 m; default: every scan)
  Data missing? scripts/fetch-data.sh downloads and converts both datasets.

Resolutions (m):
  --tum-resolution R         Fig. 1/2 on the TUM frames (default: 0.1)
  --lidar-resolution R       Fig. 1/2 on the lidar scans (default: 0.2)
  --mapping-resolution R     Fig. 3, dynamic conflicts, multi-resolution (default: 0.3)
  --coarsening K             multi-resolution factor (default: 3)
  --sweep R1,R2,...          resolution sweep (default: 0.1,0.2,...,1.0)
  --ray-mode-resolutions R1,...  ray mode comparison (default: 0.2,0.4)

Similarity:
  --min-eigenvalue V         covariance eigenvalue floor in m^2 (default: 1e-6)

NDT-OM occupancy:
  --clamp-min L, --clamp-max L   log-odds clamp (default: the library's -2, 3.5)

Experiments (default: all):
  --experiments LIST         comma-separated subset of:
      consistency  Fig. 1 (each map vs the batch map) and Fig. 2 (self-test), TUM + lidar
      mapping      Fig. 3 (mean log-odds over time) and dynamic conflicts, lidar
      multires     0.3 m map and the 0.9 m map derived from it, vs a batch 0.9 m map
      sweep        similarity to the batch map and memory for several resolutions
      raymodes     RayMode::PerHitCell vs the reference RayMode::PerPoint
      fig4         Fig. 4a-d as 3D pictures: NDT-OM, Recursive NDT with the conflicts,
                   free cells, the derived coarse map (lidar, mapping resolution)
  -h, --help                 this text

Exit status: 0 on success, 1 on any error (one-line message on stderr), 2 on bad usage.
)";
}

}  // namespace ndtom::eval
