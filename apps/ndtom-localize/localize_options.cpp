#include "localize_options.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <thread>
#include <vector>

#include "ndtom_apps/command_line.h"
#include "ndtom_apps/option_values.h"

namespace ndtom::localizer {
namespace {

using apps::parseInteger;
using apps::parseOnOff;
using apps::parseReal;
using apps::UsageError;

const apps::OptionTable<LocalizeOptions>& optionTable() {
  using O = LocalizeOptions;
  static const auto table = apps::withHelpAndQuiet(apps::withInputOptions<O>({
      {"--max-scans",
       {true,
        [](O& o, const std::string& v) {
          o.max_scans = size_t(parseInteger("--max-scans", v, 1, int64_t(1) << 40));
        }}},
      {"--skip",
       {true,
        [](O& o, const std::string& v) {
          o.skip = size_t(parseInteger("--skip", v, 0, int64_t(1) << 40));
        }}},
      {"--decimation",
       {true,
        [](O& o, const std::string& v) {
          o.decimation = uint32_t(parseInteger("--decimation", v, 1, 1000000));
        }}},
      {"--initial",
       {true, [](O& o, const std::string& v) { o.tracking.initial = parsePose("--initial", v); }}},
      {"--relocalize",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.relocalize_after = int(parseInteger("--relocalize", v, 1, 1000000));
        }}},
      {"--global-every-scan",
       {false, [](O& o, const std::string&) { o.tracking.global_every_scan = true; }}},
      {"--recovery-radius",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.placement.recovery_radius = parseReal("--recovery-radius", v);
          if (!(o.tracking.placement.recovery_radius >= 0 && o.tracking.placement.recovery_radius <= 100))
            throw UsageError("--recovery-radius = " + v + ": must be in [0, 100] m");
        }}},
      {"--ground-thinning",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.placement.ground_thinning = int(parseInteger("--ground-thinning", v, 1, 1000));
        }}},
      {"--retry-without-finest",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.placement.retry_without_finest = parseOnOff("--retry-without-finest", v);
        }}},
      {"--weak-sigma",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.placement.weak_direction_sigma = parseReal("--weak-sigma", v, /*allow_infinity=*/true);
        }}},
      {"--region-radius",
       {true,
        [](O& o, const std::string& v) {
          o.region_radius = parseReal("--region-radius", v);
          if (!(o.region_radius > 0 && o.region_radius <= 10000))
            throw UsageError("--region-radius = " + v + ": must be in (0, 10000] m");
        }}},
      {"--search-step",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.placement.search.position_step = parseReal("--search-step", v);
        }}},
      {"--search-yaw-step",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.placement.search.yaw_step_deg = parseReal("--search-yaw-step", v);
        }}},
      {"--reference", {true, [](O& o, const std::string& v) { o.reference_file = v; }}},
      {"--reference-format",
       {true, [](O& o, const std::string& v) { o.reference_format = apps::poseFormatFromName("--reference-format", v); }}},
      {"--method",
       {true,
        [](O& o, const std::string& v) {
          try {
            o.tracking.placement.registration.method = ndtom::registrationMethodFromString(v);
          } catch (const std::invalid_argument&) {
            throw UsageError("--method: expected p2d or d2d, got '" + v + "'");
          }
        }}},
      {"--levels", {true, [](O& o, const std::string& v) { o.tracking.placement.registration.level_factors = apps::parseLevelFactors("--levels", v); }}},
      {"--min-range",
       {true, [](O& o, const std::string& v) { o.tracking.placement.registration.min_range = parseReal("--min-range", v); }}},
      {"--max-range",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.placement.registration.max_range = parseReal("--max-range", v, /*allow_infinity=*/true);
        }}},
      {"--max-points",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.placement.registration.max_points = size_t(parseInteger("--max-points", v, 10, 100000000));
        }}},
      {"--max-iterations",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.placement.registration.max_iterations = int(parseInteger("--max-iterations", v, 1, 1000));
        }}},
      {"--outlier-ratio",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.placement.registration.outlier_ratio = parseReal("--outlier-ratio", v);
        }}},
      {"--min-matched-fraction",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.placement.registration.min_matched_fraction = parseReal("--min-matched-fraction", v);
        }}},
      {"--min-judged-fraction",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.placement.registration.min_judged_fraction = parseReal("--min-judged-fraction", v);
        }}},
      {"--max-free-fraction",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.placement.registration.max_free_fraction = parseReal("--max-free-fraction", v);
        }}},
      {"--planar", {false, [](O& o, const std::string&) { o.tracking.placement.registration.planar = true; }}},
      {"--threads",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.placement.registration.threads = int(parseInteger("--threads", v, 1, 256));
        }}},
      {"--no-pictures", {false, [](O& o, const std::string&) { o.pictures = false; }}},
      {"--live-map",
       {true,
        [](O& o, const std::string& v) { o.tracking.live.enabled = parseOnOff("--live-map", v); }}},
      {"--live-radius",
       {true,
        [](O& o, const std::string& v) {
          o.tracking.live.radius = parseReal("--live-radius", v);
          if (!(o.tracking.live.radius >= 5 && o.tracking.live.radius <= 10000))
            throw UsageError("--live-radius = " + v + ": must be in [5, 10000] m");
        }}},
      {"--save-map",
       {true,
        [](O& o, const std::string& v) {
          if (v.empty() || v.back() == '/')
            throw UsageError("--save-map " + v + ": PREFIX names a file, e.g. out/extended");
          o.save_map_prefix = v;
          o.tracking.live.keep_all = true;
        }}},
      {"--image-width",
       {true,
        [](O& o, const std::string& v) {
          o.image_width = int(parseInteger("--image-width", v, 400, 8000));
        }}},
  }));
  return table;
}

void checkComplete(const LocalizeOptions& o) {
  if (o.map_path.empty()) throw UsageError("missing MAP (see --help)");
  if (o.input.empty()) throw UsageError("missing INPUT (see --help)");
  if (o.prefix.empty()) throw UsageError("missing -o PREFIX (see --help)");
  if (o.prefix.back() == '/')
    throw UsageError("-o " + o.prefix + ": PREFIX names files, e.g. out/run, not a folder");
  if (!o.save_map_prefix.empty() && !o.tracking.live.enabled)
    throw UsageError("--save-map " + o.save_map_prefix + ": needs the live map (--live-map on)");
  std::error_code ec;
  if (!o.reference_file.empty() && !std::filesystem::is_regular_file(o.reference_file, ec))
    throw UsageError("--reference " + o.reference_file + ": no such file");
  try {
    ndtom::validate(o.tracking.placement);
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
  o.tracking.placement.registration.threads =
      int(std::max(1u, std::min(256u, std::thread::hardware_concurrency())));
  const std::vector<std::string> positional = apps::applyArguments(argc, argv, optionTable(), o);
  if (positional.size() > 2) throw UsageError("more than MAP and INPUT: '" + positional[2] + "'");
  if (positional.size() > 0) o.map_path = positional[0];
  if (positional.size() > 1) o.input = positional[1];
  o.tracking.placement.search = ndtom::fittedToLevels(o.tracking.placement.search, o.tracking.placement.registration.level_factors);
  if (!o.help) checkComplete(o);
  return o;
}

std::string helpText() {
  return
      "ndtom-localize: the pose of every scan of a log in a saved NDT-OM, by NDT scan-to-map\n"
      "registration (P2D or D2D, coarse to fine over the map's exact coarsenings).\n"
      "\n"
      "Usage: ndtom-localize MAP INPUT -o PREFIX [--initial \"x y z qx qy qz qw\"] [options]\n"
      "\n"
      "MAP: a .ndtom or .ndtommap written by ndtom-map.\n"
      "INPUT: what ndtom-map reads (rawlog, simplemap, TUM RGB-D folder, PCD folder); a PCD\n"
      "  folder needs no poses.txt (times.txt gives the time stamps if present). Points are\n"
      "  taken in the frame of their sensor (PCD, TUM) or robot (rawlog, simplemap).\n"
      "  --format F                rawlog|simplemap|tum|pcd (default: told from the path)\n"
      "  --poses FILE              the input's poses where ndtom-map would need them\n"
      "  --pose-format F           auto|kitti|tum\n"
      "  --skip N                  leave out the first N scans\n"
      "  --max-scans N             only the first N scans (after --skip)\n"
      "  --decimation N            1 point in N of each scan (1)\n"
      "\n"
      "Localization: the first scan is registered from --initial (without it, searched for in\n"
      "the whole map), each later one from a prediction: the log's odometry (rawlog), else\n"
      "the last motion again (constant velocity). A failed registration is retried from the\n"
      "last pose, then by a search around the prediction; a scan nothing places is lost.\n"
      "  --initial \"x y z qx qy qz qw\"   the first scan's pose in the map (TUM order)\n"
      "  --relocalize N            after N lost scans in a row, search the whole map (never)\n"
      "  --global-every-scan       no tracking: search every scan in the whole map\n"
      "  --recovery-radius M       the search around the prediction: x, y within M m (4) and\n"
      "                            yaw within 60 degrees\n"
      "  --ground-thinning K       one in K points on the scan's ground plane registers (100);\n"
      "                            on flat ground every ring point holds a moving lidar\n"
      "                            where a map scan's rings lie\n"
      "  --retry-without-finest on|off  a scan the whole pyramid cannot place is tried\n"
      "                            without its finest level (on)\n"
      "  --weak-sigma M            directions the scene constrains worse than M (std. dev.)\n"
      "                            keep the prediction (0.1; inf: never)\n"
      "  --live-map on|off         keep a map of the localized scans beside the prior map and\n"
      "                            register against both (the prior's cells win where both\n"
      "                            have one): tracking goes on where the prior map ends (on)\n"
      "  --live-radius M           the live map's region around the robot [m] (50)\n"
      "  --save-map PREFIX         write PREFIX.ndtom: the prior map extended by the live map\n"
      "                            (the prior map file is never changed)\n"
      "  --region-radius M         a tiled map (.ndtomtiles): tiles within M m (x, y) of the\n"
      "                            predicted pose resident, farther ones dropped; a search of\n"
      "                            the whole map loads every tile (60)\n"
      "  --search-step M           x, y grid of the searches [m] (2)\n"
      "  --search-yaw-step D       yaw grid of the searches [degrees] (30)\n"
      "  --method p2d|d2d          points to map Gaussians, or the scan's own NDT (p2d)\n"
      "  --levels 16,8,4,2         pyramid levels, coarse to fine, in map cells (16,8,4,2,1)\n"
      "  --min-range M, --max-range M   scan points used, distance to the sensor [m] (0, inf)\n"
      "  --max-points N            P2D: scan points per level at most (6000)\n"
      "  --max-iterations N        Newton iterations per level (30)\n"
      "  --outlier-ratio R         the score's outlier fraction, in (0, 1) (0.55)\n"
      "  --min-matched-fraction F  verdict: matched part of what the map can judge (0.4)\n"
      "  --min-judged-fraction F   verdict: scan share where the map has looked (0.15)\n"
      "  --max-free-fraction F     verdict: scan share in open free space, at most (0.05)\n"
      "  --planar                  only x, y and yaw change (2D)\n"
      "  --threads N               threads; the result is the same for any (all cores)\n"
      "\n"
      "Accuracy, where the input's poses are a reference (PCD poses.txt, TUM ground truth,\n"
      "simplemap) or one is given: error of each scan's pose, RMSE and largest.\n"
      "  --reference FILE          KITTI (line i = scan i) or TUM (matched by time stamp); it\n"
      "                            wins over the input's own poses\n"
      "  --reference-format F      auto|kitti|tum\n"
      "\n"
      "Output:\n"
      "  -o, --output PREFIX       PREFIX.tum (t x y z qx qy qz qw per localized scan),\n"
      "                            PREFIX.scans.csv (per scan: outcome, pose, error, which\n"
      "                            map placed it, time),\n"
      "                            PREFIX.summary.json (per scan: levels, iterations, score,\n"
      "                            matched fraction, outcome, error, time), PREFIX.top.png\n"
      "                            (the path on the map, coloured by error if known)\n"
      "  --no-pictures             skip the PNG\n"
      "  --image-width W           picture width [px] (1200)\n"
      "  -q, --quiet               no progress, no summary on stdout\n"
      "  -h, --help                this text\n"
      "\n"
      "Example: ndtom-localize out/map.ndtom scans/ -o out/loc --initial \"0 0 0 0 0 0 1\"\n"
      "         ndtom-localize out/map.ndtom scans/ -o out/loc --relocalize 3   (no start pose)\n";
}

}  // namespace ndtom::localizer
