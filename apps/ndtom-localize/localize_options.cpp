#include "localize_options.h"

#include <functional>
#include <map>
#include <sstream>
#include <thread>
#include <vector>

#include "ndtom_apps/option_values.h"

namespace ndtom::localizer {
namespace {

using apps::parseInteger;
using apps::parseReal;
using apps::UsageError;

using Handler = std::function<void(LocalizeOptions&, const std::string& value)>;

struct OptionSpec {
  bool takes_value;
  Handler handle;
};

std::vector<int> parseLevels(const std::string& text) {
  std::vector<int> levels;
  for (const std::string& item : apps::splitList(text))
    levels.push_back(int(parseInteger("--levels", item, 1, 1024)));
  return levels;
}

ndtom::io::PoseFormat poseFormatFromName(const std::string& name) {
  if (name == "auto") return ndtom::io::PoseFormat::Auto;
  if (name == "kitti") return ndtom::io::PoseFormat::Kitti;
  if (name == "tum") return ndtom::io::PoseFormat::Tum;
  throw UsageError("--pose-format: expected auto, kitti or tum, got '" + name + "'");
}

const std::map<std::string, OptionSpec>& optionTable() {
  using O = LocalizeOptions;
  static const std::map<std::string, OptionSpec> table = {
      {"-o", {true, [](O& o, const std::string& v) { o.prefix = v; }}},
      {"--output", {true, [](O& o, const std::string& v) { o.prefix = v; }}},
      {"--format",
       {true, [](O& o, const std::string& v) { o.format = mapper::inputFormatFromName(v); }}},
      {"--poses", {true, [](O& o, const std::string& v) { o.poses_file = v; }}},
      {"--pose-format",
       {true, [](O& o, const std::string& v) { o.pose_format = poseFormatFromName(v); }}},
      {"--max-scans",
       {true,
        [](O& o, const std::string& v) {
          o.max_scans = size_t(parseInteger("--max-scans", v, 1, int64_t(1) << 40));
        }}},
      {"--decimation",
       {true,
        [](O& o, const std::string& v) {
          o.decimation = uint32_t(parseInteger("--decimation", v, 1, 1000000));
        }}},
      {"--initial", {true, [](O& o, const std::string& v) { o.initial = parsePose("--initial", v); }}},
      {"--method",
       {true,
        [](O& o, const std::string& v) {
          try {
            o.registration.method = ndtom::registrationMethodFromString(v);
          } catch (const std::invalid_argument&) {
            throw UsageError("--method: expected p2d or d2d, got '" + v + "'");
          }
        }}},
      {"--levels", {true, [](O& o, const std::string& v) { o.registration.level_factors = parseLevels(v); }}},
      {"--min-range",
       {true, [](O& o, const std::string& v) { o.registration.min_range = parseReal("--min-range", v); }}},
      {"--max-range",
       {true,
        [](O& o, const std::string& v) {
          o.registration.max_range = parseReal("--max-range", v, /*allow_infinity=*/true);
        }}},
      {"--max-points",
       {true,
        [](O& o, const std::string& v) {
          o.registration.max_points = size_t(parseInteger("--max-points", v, 10, 100000000));
        }}},
      {"--max-iterations",
       {true,
        [](O& o, const std::string& v) {
          o.registration.max_iterations = int(parseInteger("--max-iterations", v, 1, 1000));
        }}},
      {"--outlier-ratio",
       {true,
        [](O& o, const std::string& v) {
          o.registration.outlier_ratio = parseReal("--outlier-ratio", v);
        }}},
      {"--min-matched-fraction",
       {true,
        [](O& o, const std::string& v) {
          o.registration.min_matched_fraction = parseReal("--min-matched-fraction", v);
        }}},
      {"--planar", {false, [](O& o, const std::string&) { o.registration.planar = true; }}},
      {"--threads",
       {true,
        [](O& o, const std::string& v) {
          o.registration.threads = int(parseInteger("--threads", v, 1, 256));
        }}},
      {"--no-pictures", {false, [](O& o, const std::string&) { o.pictures = false; }}},
      {"--image-width",
       {true,
        [](O& o, const std::string& v) {
          o.image_width = int(parseInteger("--image-width", v, 400, 8000));
        }}},
      {"--quiet", {false, [](O& o, const std::string&) { o.quiet = true; }}},
      {"-q", {false, [](O& o, const std::string&) { o.quiet = true; }}},
      {"--help", {false, [](O& o, const std::string&) { o.help = true; }}},
      {"-h", {false, [](O& o, const std::string&) { o.help = true; }}},
  };
  return table;
}

void checkComplete(const LocalizeOptions& o) {
  if (o.map_path.empty()) throw UsageError("missing MAP (see --help)");
  if (o.input.empty()) throw UsageError("missing INPUT (see --help)");
  if (o.prefix.empty()) throw UsageError("missing -o PREFIX (see --help)");
  if (o.prefix.back() == '/')
    throw UsageError("-o " + o.prefix + ": PREFIX names files, e.g. out/run, not a folder");
  if (!o.initial) throw UsageError("missing --initial \"x y z qx qy qz qw\" (the first scan's pose)");
  try {
    ndtom::validate(o.registration);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

}  // namespace

Eigen::Isometry3d parsePose(const std::string& option, const std::string& text) {
  std::istringstream in(text);
  std::vector<double> v;
  for (std::string item; in >> item;) v.push_back(parseReal(option, item));
  if (v.size() != 7)
    throw UsageError(option + " \"" + text + "\": expected 7 numbers, x y z qx qy qz qw");
  try {
    return ndtom::io::poseFromTranslationQuaternion(v.data(), v[3], v[4], v[5], v[6]);
  } catch (const std::invalid_argument& e) {
    throw UsageError(option + " \"" + text + "\": " + e.what());
  }
}

LocalizeOptions parseLocalizeOptions(int argc, char** argv) {
  LocalizeOptions o;
  o.registration.threads = int(std::max(1u, std::min(256u, std::thread::hardware_concurrency())));
  const auto& table = optionTable();
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i], value;
    const size_t eq = arg.find('=');
    const bool inline_value = arg.rfind("--", 0) == 0 && eq != std::string::npos;
    if (inline_value) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
    }
    if (arg.size() < 2 || arg[0] != '-') {
      positional.push_back(arg);
      continue;
    }
    const auto spec = table.find(arg);
    if (spec == table.end()) throw UsageError(arg + ": unknown option (see --help)");
    if (!spec->second.takes_value && inline_value) throw UsageError(arg + ": takes no value");
    if (spec->second.takes_value && !inline_value) {
      if (i + 1 >= argc) throw UsageError(arg + ": missing value");
      value = argv[++i];
    }
    spec->second.handle(o, value);
  }
  if (positional.size() > 2) throw UsageError("more than MAP and INPUT: '" + positional[2] + "'");
  if (positional.size() > 0) o.map_path = positional[0];
  if (positional.size() > 1) o.input = positional[1];
  if (!o.help) checkComplete(o);
  return o;
}

std::string helpText() {
  return
      "ndtom-localize: the pose of every scan of a log in a saved NDT-OM, by NDT scan-to-map\n"
      "registration (P2D or D2D, coarse to fine over the map's exact coarsenings).\n"
      "\n"
      "Usage: ndtom-localize MAP INPUT -o PREFIX --initial \"x y z qx qy qz qw\" [options]\n"
      "\n"
      "MAP: a .ndtom or .ndtommap written by ndtom-map.\n"
      "INPUT: what ndtom-map reads (rawlog, simplemap, TUM RGB-D folder, PCD folder); a PCD\n"
      "  folder needs no poses.txt (times.txt gives the time stamps if present). Points are\n"
      "  taken in the frame of their sensor (PCD, TUM) or robot (rawlog, simplemap).\n"
      "  --format F                rawlog|simplemap|tum|pcd (default: told from the path)\n"
      "  --poses FILE              the input's poses where ndtom-map would need them\n"
      "  --pose-format F           auto|kitti|tum\n"
      "  --max-scans N             only the first N scans\n"
      "  --decimation N            1 point in N of each scan (1)\n"
      "\n"
      "Localization: the first scan is registered from --initial, each later one from the\n"
      "previous result moved by the last motion (constant velocity).\n"
      "  --initial \"x y z qx qy qz qw\"   the first scan's pose in the map (TUM order)\n"
      "  --method p2d|d2d          points to map Gaussians, or the scan's own NDT (p2d)\n"
      "  --levels 16,8,4,2         pyramid levels, coarse to fine, in map cells (16,8,4,2,1)\n"
      "  --min-range M, --max-range M   scan points used, distance to the sensor [m] (0, inf)\n"
      "  --max-points N            P2D: scan points per level at most (6000)\n"
      "  --max-iterations N        Newton iterations per level (30)\n"
      "  --outlier-ratio R         the score's outlier fraction, in (0, 1) (0.55)\n"
      "  --min-matched-fraction F  verdict: matched part of the scan, in [0, 1] (0.4)\n"
      "  --planar                  only x, y and yaw change (2D)\n"
      "  --threads N               threads; the result is the same for any (all cores)\n"
      "\n"
      "Output:\n"
      "  -o, --output PREFIX       PREFIX.tum (t x y z qx qy qz qw per scan, map frame),\n"
      "                            PREFIX.summary.json (per scan: levels, iterations, score,\n"
      "                            matched fraction, verdict, time), PREFIX.top.png (the path\n"
      "                            on the map seen from above)\n"
      "  --no-pictures             skip the PNG\n"
      "  --image-width W           picture width [px] (1200)\n"
      "  -q, --quiet               no progress, no summary on stdout\n"
      "  -h, --help                this text\n"
      "\n"
      "Example: ndtom-localize out/map.ndtom scans/ -o out/loc --initial \"0 0 0 0 0 0 1\"\n";
}

}  // namespace ndtom::localizer
