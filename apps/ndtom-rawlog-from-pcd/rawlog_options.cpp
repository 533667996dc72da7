#include "rawlog_options.h"

#include <map>
#include <vector>

#include "ndtom_apps/command_line.h"
#include "ndtom_apps/option_values.h"

namespace ndtom::rawlog {
namespace {

using apps::parseInteger;
using apps::parseReal;
using apps::UsageError;

double parseStd(const std::string& option, const std::string& text) {
  const double v = parseReal(option, text);
  if (!(v >= 0)) throw UsageError(option + " " + text + ": must be >= 0");
  return v;
}

const apps::OptionTable<RawlogOptions>& optionTable() {
  using O = RawlogOptions;
  static const auto table = apps::withHelpAndQuiet<O>({
      {"-o", {true, [](O& o, const std::string& v) { o.prefix = v; }}},
      {"--output", {true, [](O& o, const std::string& v) { o.prefix = v; }}},
      {"--scans",
       {true, [](O& o, const std::string& v) { o.log_scans = parseScanRange("--scans", v); }}},
      {"--map-scans",
       {true, [](O& o, const std::string& v) { o.map_scans = parseScanRange("--map-scans", v); }}},
      {"--decimation",
       {true,
        [](O& o, const std::string& v) {
          o.decimation = uint32_t(parseInteger("--decimation", v, 1, 1000000));
        }}},
      {"--odometry-std-xyz",
       {true,
        [](O& o, const std::string& v) { o.noise.std_xyz = parseStd("--odometry-std-xyz", v); }}},
      {"--odometry-std-deg",
       {true,
        [](O& o, const std::string& v) { o.noise.std_deg = parseStd("--odometry-std-deg", v); }}},
      {"--seed",
       {true,
        [](O& o, const std::string& v) {
          o.noise.seed = uint64_t(parseInteger("--seed", v, 0, INT64_MAX));
        }}},
  });
  return table;
}

void checkComplete(const RawlogOptions& o) {
  if (o.folder.empty()) throw UsageError("missing FOLDER (see --help)");
  if (o.prefix.empty()) throw UsageError("missing -o PREFIX (see --help)");
  if (o.prefix.back() == '/')
    throw UsageError("-o " + o.prefix + ": PREFIX names files, e.g. out/run, not a folder");
}

}  // namespace

ScanRange parseScanRange(const std::string& option, const std::string& text) {
  const size_t colon = text.find(':');
  if (colon == std::string::npos)
    throw UsageError(option + " " + text + ": expected FIRST:LAST, e.g. 0:29");
  const int64_t max = int64_t(1) << 40;
  ScanRange r;
  r.first = size_t(parseInteger(option, text.substr(0, colon), 0, max));
  r.last = size_t(parseInteger(option, text.substr(colon + 1), 0, max));
  if (r.last < r.first) throw UsageError(option + " " + text + ": LAST is before FIRST");
  return r;
}

RawlogOptions parseRawlogOptions(int argc, char** argv) {
  RawlogOptions o;
  const std::vector<std::string> positional = apps::applyArguments(argc, argv, optionTable(), o);
  if (positional.size() > 1) throw UsageError("more than one FOLDER: '" + positional[1] + "'");
  if (!positional.empty()) o.folder = positional[0];
  if (!o.help) checkComplete(o);
  return o;
}

std::string helpText() {
  return "ndtom-rawlog-from-pcd: a folder of lidar scans with poses as the input of MRPT's\n"
         "pf-localization: a rawlog of (odometry, point cloud) pairs, the poses as ground truth,\n"
         "and optionally a simplemap of the scans to build the map from.\n"
         "\n"
         "Usage: ndtom-rawlog-from-pcd FOLDER -o PREFIX [options]\n"
         "\n"
         "FOLDER: *.pcd (points in the sensor frame, taken in natural order), poses.txt (KITTI:\n"
         "  line i is [R|t] of the i-th scan, sensor -> world) and times.txt (one time stamp\n"
         "  per line; without it, scan i is at i seconds).\n"
         "  --scans A:B               the rawlog's scans, A to B included (all)\n"
         "  --map-scans A:B           also write PREFIX.simplemap of scans A to B at their poses\n"
         "  --decimation N            1 point in N of each scan (1)\n"
         "\n"
         "Odometry: each CActionRobotMovement3D holds the increment between consecutive poses\n"
         "(x, y, z, yaw, pitch, roll) plus independent Gaussian noise, and declares that noise\n"
         "as its covariance. The first scan's action is a zero increment.\n"
         "  --odometry-std-xyz M      noise on x, y, z [m] (0.05)\n"
         "  --odometry-std-deg D      noise on yaw, pitch, roll [deg] (1)\n"
         "  --seed N                  of the noise (1)\n"
         "\n"
         "Output:\n"
         "  -o, --output PREFIX       PREFIX.rawlog (actions and sensory frames, each with one\n"
         "                            CObservationPointCloud labelled LIDAR, sensor pose = robot\n"
         "                            pose), PREFIX.gt.txt (time x y z yaw pitch roll per scan,\n"
         "                            radians: pf-localization's ground_truth_path_file)\n"
         "  -q, --quiet               no progress\n"
         "  -h, --help                this text\n"
         "\n"
         "Example: ndtom-rawlog-from-pcd scans/ -o out/balm --map-scans 0:29\n";
}

}  // namespace ndtom::rawlog
