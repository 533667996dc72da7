#include "world_options.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "ndtom_apps/command_line.h"
#include "ndtom_apps/option_values.h"

namespace ndtom::world {

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
      {"--km", {true, [&](WorldOptions& w, const std::string& v) {
                  w.route.length = 1000 * positive("--km", v, 10000);
                }}},
      {"--step", {true, [&](WorldOptions& w, const std::string& v) {
                    w.route.step = positive("--step", v, 100);
                  }}},
      {"--blocks", {true, [](WorldOptions& w, const std::string& v) {
                      w.city.blocks_x = w.city.blocks_y = int(parseInteger("--blocks", v, 1, 1000));
                      w.city_size_given = true;
                    }}},
      {"--margin", {true, [](WorldOptions& w, const std::string& v) {
                      w.route.margin = int(parseInteger("--margin", v, 0, 100));
                    }}},
      {"--seed", {true, [](WorldOptions& w, const std::string& v) {
                    w.city.seed = w.route.seed = w.lidar.seed =
                        uint64_t(parseInteger("--seed", v, 0, INT64_MAX));
                  }}},
      {"--noise-seed", {true, [](WorldOptions& w, const std::string& v) {
                          w.noise_seed = uint64_t(parseInteger("--noise-seed", v, 0, INT64_MAX));
                        }}},
      {"--rings", {true, [](WorldOptions& w, const std::string& v) {
                     w.lidar.rings = int(parseInteger("--rings", v, 1, 512));
                   }}},
      {"--azimuth-steps", {true, [](WorldOptions& w, const std::string& v) {
                             w.lidar.azimuth_steps = int(parseInteger("--azimuth-steps", v, 1, 36000));
                           }}},
      {"--max-range", {true, [&](WorldOptions& w, const std::string& v) {
                         w.lidar.max_range = positive("--max-range", v, 1000);
                       }}},
      {"--noise", {true, [](WorldOptions& w, const std::string& v) {
                     const double x = parseReal("--noise", v);
                     if (!(x >= 0 && x <= 1)) throw apps::UsageError("--noise " + v + ": must be in [0, 1] m");
                     w.lidar.range_noise = x;
                   }}},
      {"--speed", {true, [&](WorldOptions& w, const std::string& v) {
                     w.speed = positive("--speed", v, 100);
                   }}},
      {"--threads", {true, [](WorldOptions& w, const std::string& v) {
                       w.threads = int(parseInteger("--threads", v, 1, 256));
                     }}},
  };
  const auto positional = apps::applyArguments(argc, argv, table, o);
  if (o.help) return o;
  if (positional.size() != 1) throw apps::UsageError("give one output folder (see --help)");
  o.out = positional[0];
  if (o.noise_seed) o.lidar.seed = *o.noise_seed;  // whatever the order with --seed
  if (o.route.length / o.route.step > 1e7)
    throw apps::UsageError("--km / --step: over 10 million scans");
  if (!o.city_size_given)
    o.city.blocks_x = o.city.blocks_y =
        blocksForRoute(o.route.length, o.city.block_pitch) + 2 * o.route.margin;
  else if (2 * o.route.margin >= o.city.blocks_x)
    throw apps::UsageError("--margin: leaves no block inside a city of " +
                           std::to_string(o.city.blocks_x) + " blocks a side");
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
         "  --rings N            lidar rings, -25..+15 deg (32)\n"
         "  --azimuth-steps N    rays per ring per turn (900)\n"
         "  --max-range R        [m] (80); rays reaching nothing give no point\n"
         "  --noise S            range noise sigma [m] (0.02)\n"
         "  --speed V            [m/s] for times.txt (10)\n"
         "  --threads N          scans simulated in parallel (the machine's cores)\n"
         "  -q, --quiet          no progress, no summary\n";
}

}  // namespace ndtom::world
