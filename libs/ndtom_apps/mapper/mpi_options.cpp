#include "ndtom_apps/mpi_options.h"

#include <vector>

#include "ndtom/map/tile_index.h"
#include "ndtom_apps/option_values.h"

namespace ndtom::mapper {

MpiOptions parseMpiOptions(int argc, char** argv) {
  MpiOptions o;
  bool rank_tiles_given = false;
  std::vector<char*> rest{argv[0]};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw apps::UsageError(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--scan-input") {
      const std::string v = value();
      if (v == "each") {
        o.scan_input = ScanInput::EachReads;
      } else if (v == "broadcast") {
        o.scan_input = ScanInput::Broadcast;
      } else {
        throw apps::UsageError("--scan-input '" + v + "': use each or broadcast");
      }
    } else if (arg == "--ray-share") {
      const std::string v = value();
      if (v == "tiles") {
        o.ray_share = RayShare::Tiles;
      } else if (v == "rays") {
        o.ray_share = RayShare::Rays;
      } else {
        throw apps::UsageError("--ray-share '" + v + "': use tiles or rays");
      }
    } else if (arg == "--rank-tiles") {
      o.rank_tiles = int(apps::parseInteger("--rank-tiles", value(), 1, ndtom::kMaxTileBlocks));
      rank_tiles_given = true;
    } else {
      rest.push_back(argv[i]);
    }
  }
  if (!rank_tiles_given) o.rank_tiles = defaultRankTiles(o.ray_share);
  o.map = parseMapperOptions(int(rest.size()), rest.data());
  if (o.map.passes != 1) throw apps::UsageError("--passes: ndtom-map-mpi makes one pass");
  if (o.map.resident_budget_mb > 0)  // each process holds only its tiles already
    throw apps::UsageError("--resident-budget: not with ndtom-map-mpi (use more processes)");
  return o;
}

std::string mpiHelpText() {
  return "Usage: mpirun -np N ndtom-map-mpi INPUT -o PREFIX [options]\n"
         "\n"
         "ndtom-map with the insertion spread over N MPI processes. Space is dealt out in\n"
         "tiles (a hash of the tile over the processes); every process inserts every scan,\n"
         "walks a share of its rays and updates only its own tiles' cells, so the map is the\n"
         "one ndtom-map builds, bit for bit. Process 0 gathers the parts and writes\n"
         "ndtom-map's outputs, and PREFIX.mpi.json with each process's figures.\n"
         "\n"
         "  --scan-input each|broadcast  each process reads the input itself (a shared file\n"
         "                            system; the default), or process 0 reads and broadcasts\n"
         "  --rank-tiles B            tiles of B blocks (8 cells) a side are dealt out\n"
         "                            (Default: 1 with --ray-share rays, 4 with tiles)\n"
         "  --ray-share rays|tiles    each process walks a share of the rays whole and sends\n"
         "                            the counts in other tiles to their owners (the default:\n"
         "                            less work, a message per scan), or walks every ray's\n"
         "                            stretches through its own tiles (no messages)\n"
         "\n"
         "Every ndtom-map option applies except --passes (one pass) and --resident-budget.\n"
         "ndtom-map's help:\n\n" +
         helpText();
}

}  // namespace ndtom::mapper
