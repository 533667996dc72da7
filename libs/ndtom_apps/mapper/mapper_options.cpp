#include "ndtom_apps/mapper_options.h"

#include <algorithm>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include "ndtom/map/tile_index.h"
#include "ndtom_apps/command_line.h"
#include "ndtom_apps/option_values.h"

namespace ndtom::mapper {
namespace {

using apps::parseInteger;
using apps::parseReal;
using apps::UsageError;

double positive(const std::string& option, const std::string& text) {
  const double v = parseReal(option, text);
  if (!(v > 0)) throw UsageError(option + " = " + text + ": must be > 0");
  return v;
}

const apps::OptionTable<MapperOptions>& optionTable() {
  using O = MapperOptions;
  static const auto table = apps::withHelpAndQuiet(apps::withInputOptions<O>({
      {"--pose-time-tolerance",
       {true,
        [](O& o, const std::string& v) {
          o.pose_time_tolerance = positive("--pose-time-tolerance", v);
        }}},
      {"--fx", {true, [](O& o, const std::string& v) { o.camera.fx = positive("--fx", v); }}},
      {"--fy", {true, [](O& o, const std::string& v) { o.camera.fy = positive("--fy", v); }}},
      {"--cx", {true, [](O& o, const std::string& v) { o.camera.cx = parseReal("--cx", v); }}},
      {"--cy", {true, [](O& o, const std::string& v) { o.camera.cy = parseReal("--cy", v); }}},
      {"--depth-scale",
       {true,
        [](O& o, const std::string& v) { o.camera.depth_scale = positive("--depth-scale", v); }}},
      {"--max-scans",
       {true,
        [](O& o, const std::string& v) {
          o.max_scans = size_t(parseInteger("--max-scans", v, 1, int64_t(1) << 40));
        }}},
      {"--min-travel",
       {true,
        [](O& o, const std::string& v) { o.motion.min_travel = positive("--min-travel", v); }}},
      {"--min-turn",
       {true,
        [](O& o, const std::string& v) {
          o.motion.min_turn_deg = positive("--min-turn", v);
          if (o.motion.min_turn_deg > 180)
            throw UsageError("--min-turn = " + v + ": must be <= 180");
        }}},
      {"--config", {true, [](O& o, const std::string& v) { o.insertion.config_file = v; }}},
      {"--section", {true, [](O& o, const std::string& v) { o.insertion.section = v; }}},
      {"--coarse",
       {true,
        [](O& o, const std::string& v) { o.coarse = int(parseInteger("--coarse", v, 2, 64)); }}},
      {"--passes",
       {true,
        [](O& o, const std::string& v) { o.passes = int(parseInteger("--passes", v, 1, 1000)); }}},
      {"--no-pictures", {false, [](O& o, const std::string&) { o.pictures = false; }}},
      {"--octomap", {false, [](O& o, const std::string&) { o.octomap = true; }}},
      {"--tiles",
       {true,
        [](O& o, const std::string& v) {
          o.tile_blocks = int(parseInteger("--tiles", v, 1, ndtom::kMaxTileBlocks));
        }}},
      {"--resident-budget",
       {true,
        [](O& o, const std::string& v) {
          o.resident_budget_mb = positive("--resident-budget", v);
          // Whole bytes, and a budget no machine has is a typing error.
          if (o.resident_budget_mb < 1e-6 || o.resident_budget_mb > 1e12)
            throw UsageError("--resident-budget = " + v + ": must be in [1e-6, 1e12] MB");
        }}},
      {"--spill-dir", {true, [](O& o, const std::string& v) { o.spill_dir = v; }}},
      {"--image-width",
       {true,
        [](O& o, const std::string& v) {
          o.image_width = int(parseInteger("--image-width", v, 400, 8000));
        }}},
      {"--max-ellipsoids",
       {true,
        [](O& o, const std::string& v) {
          o.max_ellipsoids = uint32_t(parseInteger("--max-ellipsoids", v, 1, 10000000));
        }}},
      {"--ellipsoid-detail",
       {true,
        [](O& o, const std::string& v) {
          o.ellipsoid_detail = int(parseInteger("--ellipsoid-detail", v, 0, 4));
        }}},
  }));
  return table;
}

// "--p-hit" -> "p_hit" if that is an insertion key, else "".
std::string insertionKeyOf(const std::string& option) {
  if (option.rfind("--", 0) != 0) return {};
  std::string key = option.substr(2);
  std::replace(key.begin(), key.end(), '-', '_');
  return isInsertionKey(key) ? key : std::string();
}

void checkComplete(const MapperOptions& o) {
  if (o.input.empty()) throw UsageError("missing INPUT (see --help)");
  if (o.prefix.empty()) throw UsageError("missing -o PREFIX (see --help)");
  if (o.prefix.back() == '/')
    throw UsageError("-o " + o.prefix + ": PREFIX names files, e.g. out/map, not a folder");
  if (o.resident_budget_mb > 0) {
    // These outputs are made from the whole map, which an out-of-core build never holds.
    if (o.coarse)
      throw UsageError("--coarse needs the whole map in memory: not with --resident-budget");
    if (o.octomap)
      throw UsageError("--octomap needs the whole map in memory: not with --resident-budget");
  } else if (!o.spill_dir.empty()) {
    throw UsageError("--spill-dir " + o.spill_dir + ": only with --resident-budget");
  }
}

}  // namespace

MapperOptions parseMapperOptions(int argc, char** argv) {
  MapperOptions o;
  const auto& table = optionTable();
  // Insertion options (--resolution, ...) go to the map's own loader, by their .ini key.
  const auto takes_value = [&](const std::string& name) -> std::optional<bool> {
    if (!insertionKeyOf(name).empty()) return true;
    const auto spec = table.find(name);
    if (spec == table.end()) return std::nullopt;
    return spec->second.takes_value;
  };
  for (const apps::Argument& a : apps::splitArguments(argc, argv, takes_value)) {
    if (a.positional()) {
      if (!o.input.empty()) throw UsageError("more than one INPUT: '" + a.value + "'");
      o.input = a.value;
    } else if (const std::string key = insertionKeyOf(a.name); !key.empty()) {
      o.insertion.overrides.emplace_back(key, a.value);
    } else {
      table.at(a.name).handle(o, a.value);
    }
  }
  if (!o.help) checkComplete(o);
  return o;
}

std::string helpText() {
  std::ostringstream s;
  s << "ndtom-map: builds an NDT Occupancy Map (Saarinen et al. 2013) from scans with known\n"
       "poses and writes the map, an MRPT scene, pictures and a summary.\n"
       "\n"
       "Usage: ndtom-map INPUT -o PREFIX [options]\n"
       "\n"
       "INPUT (the kind is told from the path; --format rawlog|simplemap|tum|pcd overrides):\n"
       "  FILE.rawlog[.gz]      MRPT rawlog, either format; poses from its odometry or --poses\n"
       "  FILE.simplemap[.gz]   MRPT simplemap: keyframes with their poses\n"
       "  FOLDER (TUM RGB-D)    depth/*.png + associations.txt (or depth.txt + groundtruth.txt)\n"
       "  FOLDER (PCD)          *.pcd scans (natural order: 0, 1, ..., 10) + poses.txt\n"
       "\n"
       "Poses:\n"
       "  --poses FILE              trajectory, KITTI (12 numbers a line) or TUM (t x y z qx qy\n"
       "                            qz qw). rawlog: robot poses, TUM matched by time stamp, KITTI\n"
       "                            line i = i-th scan. PCD folder: sensor poses, line i = i-th\n"
       "                            scan (default FOLDER/poses.txt)\n"
       "  --pose-format F           auto|kitti|tum (auto: 12 numbers a line is KITTI)\n"
       "  --pose-time-tolerance S   largest time stamp gap for a TUM match [s] (0.02)\n"
       "  --max-scans N             only the first N scans\n"
       "  --min-travel M            insert a scan only if the sensor moved >= M metres or (with\n"
       "                            --min-turn) turned >= DEG degrees since the last inserted\n"
       "  --min-turn DEG            scan (the paper inserts a scan every 0.05 m; default: all)\n"
       "  --fx, --fy, --cx, --cy, --depth-scale   TUM RGB-D depth camera (525, 525, 319.5,\n"
       "                            239.5, 5000 units per metre)\n"
       "\n"
       "Map (the keys of the MRPT plugin's insertOpts; the command line overrides the file):\n"
       "  --config FILE.ini         read them from an MRPT .ini file\n"
       "  --section NAME            its section ("
    << kDefaultInsertionSection << ")\n";
  for (const auto& key : insertionKeys()) {
    std::string option = "--" + key.name;
    std::replace(option.begin(), option.end(), '_', '-');
    option += " X";
    s << "  " << option << std::string(option.size() < 26 ? 26 - option.size() : 1, ' ') << key.help
      << "\n";
  }
  s << "                            --memory-budget by default: 4 x the input's size on disk,\n"
       "                            at least 512 MB, at most half the memory available (the\n"
       "                            summary says which)\n"
       "  --coarse K                also write a map K times coarser (exact merge of cells)\n"
       "  --passes N                replay the input N times, cells and memory after each (1)\n"
       "\n"
       "Out of core (maps bigger than memory):\n"
       "  --resident-budget MB      keep about MB megabytes of map in memory: the tiles no scan\n"
       "                            used for the longest are spilled to disk and read back when a\n"
       "                            scan reaches them (the same map, bit for bit). Writes only\n"
       "                            PREFIX.ndtomtiles (tiles of --tiles B blocks, default "
    << kDefaultOutOfCoreTileBlocks
    << ")\n"
       "                            and PREFIX.summary.json: the single-file map, MRPT map, scene\n"
       "                            and pictures need the whole map in memory, so they are not\n"
       "                            written (nor --coarse, --octomap). Memory is the budget plus\n"
       "                            the tiles one scan reaches (its points cut at max_range)\n"
       "  --spill-dir DIR           spill into a new folder in DIR (default: PREFIX's folder);\n"
       "                            removed at the end\n"
       "\n"
       "Output:\n"
       "  -o, --output PREFIX       PREFIX.ndtom (project format), PREFIX.ndtommap (MRPT\n"
       "                            CNDTOccupancyMap), PREFIX.3Dscene (SceneViewer3D),\n"
       "                            PREFIX.top.png, PREFIX.3d.png, PREFIX.summary.json\n"
       "  --no-pictures             skip the PNGs\n"
       "  --octomap                 also PREFIX.bt: the map as an OctoMap (octovis, OctoMap's\n"
       "                            tools), occupied and free cells with their log-odds\n"
       "  --tiles B                 also PREFIX.ndtomtiles: the map in tiles of B blocks (8 "
       "cells)\n"
       "                            a side, for loading by region (ndtom-localize)\n"
       "  --image-width W           picture width [px] (1200)\n"
       "  --max-ellipsoids N        Gaussians drawn in the 3D picture and scene (50000)\n"
       "  --ellipsoid-detail D      their tessellation, 0-4: 8*4^D triangles each (by their\n"
       "                            number: 2 up to 8000, 1 up to 20000, else 0); lowered\n"
       "                            where the scene would pass 1048576 triangles\n"
       "  -q, --quiet               no progress, no summary on stdout\n"
       "  -h, --help                this text\n"
       "\n"
       "Example: ndtom-map share/data/tum-fr2-pioneer-slam2 -o out/tum  (from the source tree)\n"
       "         ndtom-map /usr/share/ndtom/data/tum-fr2-pioneer-slam2 -o out/tum  (.deb)\n";
  return s.str();
}

}  // namespace ndtom::mapper
