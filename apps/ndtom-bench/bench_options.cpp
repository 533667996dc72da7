#include "bench_options.h"

#include <limits>

#include "ndtom_apps/command_line.h"

namespace ndtom::bench {

namespace {

constexpr apps::NamedValue<SystemKind> kSystems[] = {{"ndtom-point", SystemKind::NdtomPerPoint},
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

void setOption(BenchOptions& o, const std::string& name, const std::string& value) {
  if (name == "--dataset") {
    o.datasets.push_back(value);
  } else if (name == "--scans") {
    o.max_scans = parseCount(name, value, 1);
  } else if (name == "--resolutions") {
    o.resolutions = parseResolutions(value);
  } else if (name == "--systems") {
    o.systems = apps::parseNamedList(name, value, kSystems);
  } else if (name == "--threads") {
    const std::vector<int64_t> threads = apps::parseIntegerList(name, value, 1, 1000000);
    o.threads.assign(threads.begin(), threads.end());
  } else if (name == "--max-range") {
    o.max_range = value == "none" ? std::numeric_limits<double>::infinity()
                                  : apps::parseReal(name, value, true);
    if (!(o.max_range > 0)) throw apps::UsageError("--max-range: must be > 0 m");
  } else if (name == "--real-time") {
    for (const std::string& item : apps::splitList(value)) {
      const double ms = apps::parseReal(name, item);
      if (!(ms > 0)) throw apps::UsageError("--real-time: " + item + " ms must be > 0");
      o.real_time_ms.push_back(ms);
    }
    if (o.real_time_ms.empty()) throw apps::UsageError("--real-time: empty list");
  } else if (name == "--registration-scans") {
    o.registration_scans = parseCount(name, value, 0);
  } else if (name == "--repeats") {
    o.repeats = parseCount(name, value, 1);
  } else if (name == "--csv") {
    o.csv_path = value;
  } else if (name == "--plot") {
    o.plot_prefix = value;
  } else {
    throw apps::unknownOption(name);
  }
}

}  // namespace

const char* systemName(SystemKind kind) {
  return apps::nameOf(kind, kSystems);
}

bool isNdtom(SystemKind kind) {
  return kind == SystemKind::NdtomPerPoint || kind == SystemKind::NdtomPerHitCell;
}

BenchOptions parseArguments(int argc, const char* const argv[]) {
  BenchOptions o = apps::parseOptionPairs<BenchOptions>(argc, argv, setOption);
  if (!o.help && o.datasets.empty()) throw apps::UsageError("no --dataset given (see --help)");
  return o;
}

std::string helpText(const std::string& program) {
  return "Usage: " + program + R"( --dataset DIR|synthetic [options]

Replays the same scans into NDT-OM, OctoMap and MRPT's COccupancyGridMap3D, one after the
other in this process, and reports time per scan, rates, memory and cell counts per system and
resolution, the ratios to OctoMap and COccupancyGridMap3D, and the project's targets.
Insertion is timed, then registration against the map built (see --registration-scans).
Per stage, the time on one thread and in parallel regions is reported, with the speed-up
Amdahl's law predicts from it at 2, 4, 8 and 16 threads. Progress goes to stderr, the summary
table to stdout.

  --dataset DIR|synthetic  a folder with fullN.pcd scans (sensor frame) and poses.txt (KITTI)
                           (scripts/fetch-data.sh downloads the BALM scans in this layout),
                           or 'synthetic' for the generated 64-ring, 115,200-point sequence;
                           repeat the option for several datasets
  --scans N                first N scans of each dataset (default: all; synthetic: 60)
  --resolutions LIST       comma-separated, m (default: 0.1,0.2,0.4,0.8)
  --systems LIST           of ndtom-point, ndtom-hitcell, octomap, mrpt-grid3d (default: all)
  --threads LIST           NDT-OM insertion threads (default: 1,2 if the core supports
                           threads, else 1)
  --max-range M|none       rays longer than M are truncated, for every system (default: 30;
                           none: no cut, as the paper)
  --real-time MS,...       scan periods (ms): drawn in the plot, and the finest resolution
                           from which each system's median stays within them is reported
  --repeats N              full runs per system and resolution; times are pooled (default: 1;
                           the side-by-side thread comparison runs at least 3, and at least
                           6 s of the multi-thread side)
  --registration-scans N   register the first N scans (at most all) against the map of
                           ndtom-point/t1 (else the first NDT-OM map), each from its pose
                           moved 0.3 m and turned 3 deg, at each --threads (default: 20;
                           0: none)
  --csv FILE               write one row per system, threads and resolution, and per stage
                           of each NDT-OM and registration run FILE.stages.csv (FILE less
                           its .csv)
  --plot PREFIX            write PREFIX_<dataset>.png: time per scan against resolution
  --quiet                  no progress output
  --help                   this text
)";
}

}  // namespace ndtom::bench
