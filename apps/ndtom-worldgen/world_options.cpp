#include "world_options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "ndtom/map/memory_budget.h"
#include "ndtom_apps/command_line.h"
#include "ndtom_apps/option_values.h"

namespace ndtom::world {
namespace {

std::string bytesText(double bytes) {
  char text[32];
  if (bytes >= 1e12)
    std::snprintf(text, sizeof text, "%.1f TB", bytes / 1e12);
  else if (bytes >= 1e9)
    std::snprintf(text, sizeof text, "%.1f GB", bytes / 1e9);
  else
    std::snprintf(text, sizeof text, "%.1f MB", bytes / 1e6);
  return text;
}

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

// The memory budget's part of a message: ndtom-map's wording.
std::string overBudget(uint64_t budget) {
  return "over the memory budget of " + bytesText(double(budget)) + " (--memory-budget, in MB)";
}

// Refuses a run that would not fit the memory budget, naming what takes most of it; with no
// --threads, first fewer threads (down to one) if that is enough.
void checkMemory(WorldOptions& o) {
  const double city = double(CityWorld::estimatedBytes(o.city));
  const double route = double(routeBytes(o.city, o.route));
  const double scan = double(scanBytes(o.lidar));
  constexpr double kFixed = 5e5;  // a batch of poses, the text files' buffers
  const double budget = double(o.memory_budget);
  const auto fits = [&](int threads) { return kFixed + city + route + threads * scan <= budget; };
  if (fits(o.threads)) return;
  if (!o.threads_given && fits(1)) {
    while (!fits(o.threads)) --o.threads;
    return;
  }
  const std::string blocks =
      std::to_string(o.city.blocks_x) + "x" + std::to_string(o.city.blocks_y);
  const double threads_scan = (o.threads_given ? o.threads : 1) * scan;
  if (city >= threads_scan && city >= route)
    throw apps::UsageError(
        (o.city_size_given ? "--blocks " + std::to_string(o.city.blocks_x)
                           : "--km " + number(o.route.length / 1000) +
                                 (o.route.margin ? " and --margin " + std::to_string(o.route.margin)
                                                 : std::string()) +
                                 " (the city is sized for the drive)") +
        ": a city of " + blocks + " blocks needs " + bytesText(city) + ", " +
        overBudget(o.memory_budget));
  if (threads_scan >= route) {
    const double rays = double(o.lidar.rings) * double(o.lidar.azimuth_steps);
    throw apps::UsageError(
        "--rings " + std::to_string(o.lidar.rings) + " x --azimuth-steps " +
        std::to_string(o.lidar.azimuth_steps) + " = " + number(rays / 1e6) +
        " M rays a scan need " + bytesText(scan) + " a thread" +
        (o.threads_given ? " x --threads " + std::to_string(o.threads) : std::string()) + " (and " +
        bytesText(city) + " for the city): " + overBudget(o.memory_budget));
  }
  throw apps::UsageError("--km " + number(o.route.length / 1000) + ": the route needs " +
                         bytesText(route) + ", " + overBudget(o.memory_budget));
}

}  // namespace

uint64_t scanBytes(const LidarModel& lidar) {
  // A point a ray at most (24 bytes), its vector growing from half that: 1.5 times while
  // it grows; the file is written in pieces of 64 kB.
  return uint64_t(36.0 * double(lidar.rings) * double(lidar.azimuth_steps)) + 100000;
}

uint64_t scanFileBytes(const LidarModel& lidar, uint64_t scans) {
  const double rays = double(lidar.rings) * double(lidar.azimuth_steps);
  const double bytes = double(scans) * (250 + 12 * rays / 2);
  return bytes < 1.8e19 ? uint64_t(bytes) : UINT64_MAX;
}

uint64_t runBytes(const WorldOptions& o) {
  const double bytes = double(CityWorld::estimatedBytes(o.city)) +
                       double(routeBytes(o.city, o.route)) + o.threads * double(scanBytes(o.lidar));
  return bytes < 1.8e19 ? uint64_t(bytes) : UINT64_MAX;
}

void checkDiskSpace(const WorldOptions& o) {
  namespace fs = std::filesystem;
  // The folder, or the nearest of its parents that exists.
  fs::path at = fs::absolute(fs::path(o.out));
  std::error_code ec;
  while (!fs::exists(at, ec) && at.has_parent_path() && at.parent_path() != at)
    at = at.parent_path();
  const fs::space_info space = fs::space(at, ec);
  if (ec) return;  // unknown: the writes will say
  const uint64_t scans = routeScans(o.route.length, o.route.step);
  // poses.txt and times.txt: ~200 and ~16 bytes a scan.
  const double need = double(scanFileBytes(o.lidar, scans)) + 220.0 * double(scans);
  if (need > double(space.available))
    throw apps::UsageError("--km " + number(o.route.length / 1000) + " / --step " +
                           number(o.route.step) + " = " + std::to_string(scans) +
                           " scans of --rings " + std::to_string(o.lidar.rings) +
                           " x --azimuth-steps " + std::to_string(o.lidar.azimuth_steps) +
                           " rays: about " + bytesText(need) + " of files, over the " +
                           bytesText(double(space.available)) + " free on the disk of " + o.out);
}

int blocksForRoute(double length, double block_pitch) {
  // A square city of n blocks a side has 2n(n+1) street segments of one pitch each.
  const double segments = 2 * length / block_pitch;
  return std::max(1, int(std::ceil(std::sqrt(segments / 2))));
}

WorldOptions parseWorldOptions(int argc, const char* const argv[]) {
  using apps::parseInteger;
  using apps::parseReal;
  WorldOptions o;
  o.threads = std::clamp(int(std::thread::hardware_concurrency()), 1, 256);
  o.memory_budget = defaultMemoryBudget();
  const auto positive = [](const std::string& name, const std::string& v, double max) {
    const double x = parseReal(name, v);
    if (!(x > 0) || x > max)
      throw apps::UsageError(name + " " + v + ": must be in (0, " + std::to_string(int(max)) + "]");
    return x;
  };
  apps::OptionTable<WorldOptions> table = {
      {"--help", {false, [](WorldOptions& w, const std::string&) { w.help = true; }}},
      {"-h", {false, [](WorldOptions& w, const std::string&) { w.help = true; }}},
      {"-q", {false, [](WorldOptions& w, const std::string&) { w.quiet = true; }}},
      {"--quiet", {false, [](WorldOptions& w, const std::string&) { w.quiet = true; }}},
      {"--km",
       {true, [&](WorldOptions& w,
                  const std::string& v) { w.route.length = 1000 * positive("--km", v, 10000); }}},
      {"--step",
       {true,
        [&](WorldOptions& w, const std::string& v) { w.route.step = positive("--step", v, 100); }}},
      {"--blocks",
       {true,
        [](WorldOptions& w, const std::string& v) {
          w.city.blocks_x = w.city.blocks_y = int(parseInteger("--blocks", v, 1, 1000));
          w.city_size_given = true;
        }}},
      {"--margin",
       {true,
        [](WorldOptions& w, const std::string& v) {
          w.route.margin = int(parseInteger("--margin", v, 0, 100));
        }}},
      {"--seed",
       {true,
        [](WorldOptions& w, const std::string& v) {
          w.city.seed = w.route.seed = w.lidar.seed =
              uint64_t(parseInteger("--seed", v, 0, INT64_MAX));
        }}},
      {"--identical-blocks",
       {false, [](WorldOptions& w, const std::string&) { w.city.identical_blocks = true; }}},
      {"--noise-seed",
       {true,
        [](WorldOptions& w, const std::string& v) {
          w.noise_seed = uint64_t(parseInteger("--noise-seed", v, 0, INT64_MAX));
        }}},
      {"--rings",
       {true,
        [](WorldOptions& w, const std::string& v) {
          w.lidar.rings = int(parseInteger("--rings", v, 1, 512));
        }}},
      {"--azimuth-steps",
       {true,
        [](WorldOptions& w, const std::string& v) {
          w.lidar.azimuth_steps = int(parseInteger("--azimuth-steps", v, 1, 36000));
        }}},
      {"--max-range",
       {true, [&](WorldOptions& w,
                  const std::string& v) { w.lidar.max_range = positive("--max-range", v, 1000); }}},
      {"--noise",
       {true,
        [](WorldOptions& w, const std::string& v) {
          const double x = parseReal("--noise", v);
          if (!(x >= 0 && x <= 1)) throw apps::UsageError("--noise " + v + ": must be in [0, 1] m");
          w.lidar.range_noise = x;
        }}},
      {"--speed",
       {true,
        [&](WorldOptions& w, const std::string& v) { w.speed = positive("--speed", v, 100); }}},
      {"--threads",
       {true,
        [](WorldOptions& w, const std::string& v) {
          w.threads = int(parseInteger("--threads", v, 1, 256));
          w.threads_given = true;
        }}},
      {"--memory-budget",
       {true,
        [](WorldOptions& w, const std::string& v) {
          const double mb = parseReal("--memory-budget", v);
          if (!(mb >= double(kMinMemoryBudget) / 1e6) || !(mb < 1.8e13))
            throw apps::UsageError("--memory-budget " + v + ": must be at least 1 MB");
          w.memory_budget = uint64_t(std::round(mb * 1e6));
        }}},
  };
  const auto positional = apps::applyArguments(argc, argv, table, o);
  if (o.help) return o;
  if (positional.size() != 1) throw apps::UsageError("give one output folder (see --help)");
  o.out = positional[0];
  if (o.noise_seed) o.lidar.seed = *o.noise_seed;  // whatever the order with --seed
  const uint64_t scans = routeScans(o.route.length, o.route.step);
  if (scans > kMaxRouteScans)
    throw apps::UsageError("--km " + number(o.route.length / 1000) + " / --step " +
                           number(o.route.step) + " = " + std::to_string(scans) +
                           " scans: over the limit of " + std::to_string(kMaxRouteScans));
  if (!o.city_size_given)
    o.city.blocks_x = o.city.blocks_y =
        blocksForRoute(o.route.length, o.city.block_pitch) + 2 * o.route.margin;
  else if (2 * o.route.margin >= o.city.blocks_x)
    throw apps::UsageError("--margin: leaves no block inside a city of " +
                           std::to_string(o.city.blocks_x) + " blocks a side");
  checkMemory(o);
  return o;
}

std::string worldHelpText() {
  return "Usage: ndtom-worldgen OUT_DIR [options]\n"
         "A procedural city (blocks of buildings, parks, poles, parked cars) and a lidar driven\n"
         "through its streets: OUT_DIR gets scan000000.pcd ... (sensor frame), poses.txt (KITTI:\n"
         "sensor -> world) and times.txt, the layout ndtom-map reads. Deterministic: the same\n"
         "options give the same files.\n"
         "  --km L               length driven [km] (2)\n"
         "  --step S             distance between scans [m] (1)\n"
         "  --blocks N           city blocks per side (default: enough for the drive, plus\n"
         "                       the margin's)\n"
         "  --margin N           rings of blocks round the driven streets (0): the drive\n"
         "                       keeps off the outer streets, city on every side\n"
         "  --seed N             world, route and noise (1)\n"
         "  --noise-seed N       the noise only: another drive of the same streets (--seed)\n"
         "  --identical-blocks   every block the same: look-alike streets\n"
         "  --rings N            lidar rings, -25..+15 deg (32)\n"
         "  --azimuth-steps N    rays per ring per turn (900)\n"
         "  --max-range R        [m] (80); rays reaching nothing give no point\n"
         "  --noise S            range noise sigma [m] (0.02)\n"
         "  --speed V            [m/s] for times.txt (10)\n"
         "  --threads N          scans simulated in parallel (the machine's cores, fewer\n"
         "                       if the memory budget holds fewer scans)\n"
         "  --memory-budget MB   memory the run may take (the library's default: a quarter of the\n"
         "                       machine's, at most 512 MB): the city (~5 kB a block, 8 B an\n"
         "                       8 m cell) and ~36 B a ray (rings x azimuth steps) a\n"
         "                       thread; larger runs are refused before they start. Scans\n"
         "                       are written as they are made: memory does not grow with\n"
         "                       --km. At most 10 million scans (--km / --step), and a run\n"
         "                       whose files would not fit the disk's free space is refused\n"
         "  -q, --quiet          no progress, no summary\n";
}

}  // namespace ndtom::world
