#include "regbench_options.h"

#include "ndtom_apps/command_line.h"

namespace ndtom::regbench {

namespace {

constexpr apps::NamedValue<SystemKind> kSystems[] = {{"ndtom-p2d", SystemKind::NdtomP2D},
                                                     {"ndtom-d2d", SystemKind::NdtomD2D},
                                                     {"mrpt-icp", SystemKind::MrptIcp},
                                                     {"pcl-ndt", SystemKind::PclNdt},
                                                     {"pcl-gicp", SystemKind::PclGicp}};

constexpr int kMaxThreads = 256;

std::vector<int> parseInts(const std::string& option, const std::string& text, int lo, int hi) {
  const std::vector<int64_t> values = apps::parseIntegerList(option, text, lo, hi);
  return {values.begin(), values.end()};
}

/// "T/R": translation (m) and rotation (degrees), e.g. "1/10".
std::vector<ErrorLevel> parseErrors(const std::string& text) {
  std::vector<ErrorLevel> out;
  for (const std::string& item : apps::splitList(text)) {
    const size_t slash = item.find('/');
    if (slash == std::string::npos)
      throw apps::UsageError("--errors: '" + item + "' is not METRES/DEGREES, e.g. 1/10");
    ErrorLevel level{apps::parseReal("--errors", item.substr(0, slash)),
                     apps::parseReal("--errors", item.substr(slash + 1))};
    if (!(level.meters >= 0 && level.meters <= 100 && level.degrees >= 0 && level.degrees <= 180))
      throw apps::UsageError("--errors: " + item + " is outside [0, 100] m / [0, 180] degrees");
    for (const ErrorLevel& l : out)
      if (l.meters == level.meters && l.degrees == level.degrees)
        throw apps::UsageError("--errors: " + item + " is listed twice");
    out.push_back(level);
  }
  if (out.empty()) throw apps::UsageError("--errors: empty list");
  return out;
}

void setOption(RegbenchOptions& o, const std::string& name, const std::string& value) {
  if (name == "--dataset") {
    o.dataset = value;
  } else if (name == "--csv") {
    o.csv_path = value;
  } else if (name == "--trials-csv") {
    o.trials_csv_path = value;
  } else if (name == "--plot") {
    o.plot_path = value;
  } else if (name == "--held-out") {
    o.held_out = parseInts(name, value, 0, 1000000);
  } else if (name == "--trials") {
    o.trials = int(apps::parseInteger(name, value, 1, 10000));
  } else if (name == "--errors") {
    o.errors = parseErrors(value);
  } else if (name == "--systems") {
    o.systems = apps::parseNamedList(name, value, kSystems);
  } else if (name == "--threads") {
    o.threads = parseInts(name, value, 1, kMaxThreads);
  } else if (name == "--resolution") {
    o.resolution = apps::parseReal(name, value);
    if (!(o.resolution >= 0.05 && o.resolution <= 2))
      throw apps::UsageError("--resolution: " + value + " m is outside [0.05, 2] m");
  } else if (name == "--max-range") {
    o.max_range = apps::parseReal(name, value);
    if (!(o.max_range > 0)) throw apps::UsageError("--max-range: must be > 0 m");
  } else if (name == "--seed") {
    o.seed = uint32_t(apps::parseInteger(name, value, 0, 4294967295LL));
  } else {
    throw apps::unknownOption(name);
  }
}

}  // namespace

RegbenchOptions parseArguments(int argc, const char* const argv[]) {
  RegbenchOptions o = apps::parseOptionPairs<RegbenchOptions>(argc, argv, setOption);
  if (!o.help && o.dataset.empty()) throw apps::UsageError("no --dataset given (see --help)");
  return o;
}

std::string helpText(const std::string& program) {
  return "Usage: " + program + R"( --dataset DIR [options]

Registers held-out lidar scans against a map of all the other scans of a sequence, from
initial errors of growing size (translation in a random horizontal direction, rotation about
the vertical axis with a random sign; fixed seeds, so every system gets the same starts),
with NDT-OM's registration (P2D and D2D) and its peers: MRPT's ICP, and PCL's NDT and GICP
when this build has PCL. A registration succeeds when it ends within 0.10 m and 1 degree of
the reference pose. Reports per system, threads and error level the success rate, the median
error of the successes, the median and p95 time per registration (each system's first call,
which builds what it caches, is reported apart), and NDT-OM's verdicts and time per pyramid
level. Progress goes to stderr, the summary (Markdown) to stdout.

  --dataset DIR        fullN.pcd scans (sensor frame) and poses.txt (KITTI, sensor -> world)
  --held-out LIST      scan numbers registered against the map of the others
                       (default: 15,30,45)
  --trials N           starts per held-out scan and error level (default: 4)
  --errors LIST        initial errors as METRES/DEGREES (default:
                       0.25/2.5,0.5/5,1/10,1.5/15,2/20,3/30,5/45)
  --systems LIST       of ndtom-p2d, ndtom-d2d, mrpt-icp, pcl-ndt, pcl-gicp (default: all that
                       this build has; pcl-* need PCL at build time: scripts/setup.sh --with-pcl)
  --threads LIST       thread counts for the systems that have a thread option (NDT-OM; PCL
                       1.13's NDT and GICP and MRPT's ICP run once, on one thread)
                       (default: 1,2)
  --resolution M       NDT-OM map cell (default: 0.2)
  --max-range M        map points farther from their sensor are left out, for every system
                       (default: 30)
  --seed N             of the starts' directions and signs (default: 15)
  --csv FILE           one row per system, threads and error level
  --trials-csv FILE    one row per registration: start, final pose, errors, verdict, time
  --plot FILE.png      success rate against the initial error, one line per system
  --quiet              no progress output
  --help               this text
)";
}

const char* systemName(SystemKind kind) {
  return apps::nameOf(kind, kSystems);
}

bool isNdtom(SystemKind kind) {
  return kind == SystemKind::NdtomP2D || kind == SystemKind::NdtomD2D;
}

bool usesThreads(SystemKind kind) {
  return isNdtom(kind);
}

}  // namespace ndtom::regbench
