#include "bench_options.h"

#include "ndtom_apps/option_values.h"

namespace ndtom::bench {

namespace {

struct NamedSystem {
  const char* name;
  SystemKind kind;
};
constexpr NamedSystem kSystems[] = {{"ndtom-point", SystemKind::NdtomPerPoint},
                                    {"ndtom-hitcell", SystemKind::NdtomPerHitCell},
                                    {"octomap", SystemKind::Octomap},
                                    {"mrpt-grid3d", SystemKind::MrptGrid3d}};

int parseCount(const std::string& option, const std::string& text, int min) {
  return int(apps::parseInteger(option, text, min, 1000000));
}

std::vector<double> parseResolutions(const std::string& text) {
  std::vector<double> out;
  for (const std::string& item : apps::splitList(text)) {
    const double r = apps::parseReal("--resolutions", item);
    if (!(r >= 0.01 && r <= 10.0))
      throw apps::UsageError("--resolutions: " + item + " m is outside [0.01, 10] m");
    out.push_back(r);
  }
  if (out.empty()) throw apps::UsageError("--resolutions: empty list");
  return out;
}

std::vector<SystemKind> parseSystems(const std::string& text) {
  std::vector<SystemKind> out;
  for (const std::string& item : apps::splitList(text)) {
    bool found = false;
    for (const NamedSystem& s : kSystems)
      if (item == s.name) {
        out.push_back(s.kind);
        found = true;
      }
    if (!found) throw apps::UsageError("--systems: unknown system '" + item + "' (see --help)");
  }
  if (out.empty()) throw apps::UsageError("--systems: empty list");
  return out;
}

std::vector<int> parseThreads(const std::string& text) {
  std::vector<int> out;
  for (const std::string& item : apps::splitList(text))
    out.push_back(parseCount("--threads", item, 1));
  if (out.empty()) throw apps::UsageError("--threads: empty list");
  return out;
}

}  // namespace

const char* systemName(SystemKind kind) {
  for (const NamedSystem& s : kSystems)
    if (s.kind == kind) return s.name;
  return "?";
}

bool isNdtom(SystemKind kind) {
  return kind == SystemKind::NdtomPerPoint || kind == SystemKind::NdtomPerHitCell;
}

BenchOptions parseArguments(int argc, const char* const argv[]) {
  BenchOptions o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      o.help = true;
      continue;
    }
    if (arg == "--quiet") {
      o.quiet = true;
      continue;
    }
    if (i + 1 >= argc) throw apps::UsageError(arg + ": missing value (see --help)");
    const std::string value = argv[++i];
    if (arg == "--dataset") {
      o.datasets.push_back(value);
    } else if (arg == "--scans") {
      o.max_scans = parseCount(arg, value, 1);
    } else if (arg == "--resolutions") {
      o.resolutions = parseResolutions(value);
    } else if (arg == "--systems") {
      o.systems = parseSystems(value);
    } else if (arg == "--threads") {
      o.threads = parseThreads(value);
    } else if (arg == "--max-range") {
      o.max_range = apps::parseReal(arg, value);
      if (!(o.max_range > 0)) throw apps::UsageError("--max-range: must be > 0 m");
    } else if (arg == "--repeats") {
      o.repeats = parseCount(arg, value, 1);
    } else if (arg == "--csv") {
      o.csv_path = value;
    } else if (arg == "--plot") {
      o.plot_prefix = value;
    } else {
      throw apps::UsageError("unknown option '" + arg + "' (see --help)");
    }
  }
  if (!o.help && o.datasets.empty()) throw apps::UsageError("no --dataset given (see --help)");
  return o;
}

std::string helpText(const std::string& program) {
  return "Usage: " + program + R"( --dataset DIR|synthetic [options]

Replays the same scans into NDT-OM, OctoMap and MRPT's COccupancyGridMap3D, one after the
other in this process, and reports time per scan, rates, memory and cell counts per system and
resolution, the ratios to OctoMap and COccupancyGridMap3D, and the project's targets.
Only insertion is timed. Progress goes to stderr, the summary table to stdout.

  --dataset DIR|synthetic  a folder with fullN.pcd scans (sensor frame) and poses.txt (KITTI),
                           or 'synthetic' for the generated 64-ring, 115,200-point sequence;
                           repeat the option for several datasets
  --scans N                first N scans of each dataset (default: all; synthetic: 60)
  --resolutions LIST       comma-separated, m (default: 0.1,0.2,0.4,0.8)
  --systems LIST           of ndtom-point, ndtom-hitcell, octomap, mrpt-grid3d (default: all)
  --threads LIST           NDT-OM insertion threads (default: 1,2 if the core supports
                           threads, else 1)
  --max-range M            rays longer than M are truncated, for every system (default: 30)
  --repeats N              full runs per system and resolution; times are pooled (default: 1;
                           the side-by-side thread comparison runs at least 3, and at least
                           6 s of the multi-thread side)
  --csv FILE               write one row per system, threads and resolution
  --plot PREFIX            write PREFIX_<dataset>.png: time per scan against resolution
  --quiet                  no progress output
  --help                   this text
)";
}

}  // namespace ndtom::bench
