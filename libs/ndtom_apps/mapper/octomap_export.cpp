#include "ndtom_apps/octomap_export.h"

#include <fcntl.h>
#include <octomap/OcTree.h>
#include <unistd.h>

#include <cstdio>
#include <stdexcept>

#include "ndtom/map/map_queries.h"

namespace ndtom::mapper {

void writeOctomapBinary(const ndtom::NdtMap& map, const std::string& path) {
  octomap::OcTree tree(map.options().resolution);
  // OctoMap's keys are cell indices offset by half its 16-bit range.
  constexpr int32_t kOffset = 32768;
  const float occupied_without_occupancy = tree.getClampingThresMaxLog();
  map.forEachCellOrdered([&](const ndtom::CellView& c) {
    const ndtom::CellState state = ndtom::cellState(map, c);
    if (state == ndtom::CellState::Unknown) return;
    octomap::OcTreeKey key;
    for (int a = 0; a < 3; ++a) {
      const int32_t k = c.index[a] + kOffset;
      if (k < 0 || k > 65535) {
        char why[200];
        std::snprintf(why, sizeof why,
                      "--octomap: the map has a cell %.1f m from the origin on axis %d, beyond "
                      "OctoMap's range of 32768 cells (%.1f m) at %g m",
                      double(c.index[a]) * map.options().resolution, a,
                      kOffset * map.options().resolution, map.options().resolution);
        throw std::runtime_error(why);
      }
      key[a] = octomap::key_type(k);
    }
    const float logodds = map.options().occupancy.enabled ? c.logodds : occupied_without_occupancy;
    tree.setNodeValue(key, logodds, /*lazy_eval=*/true);
  });
  tree.updateInnerOccupancy();
  // Debian's liboctomap prints " done." on stderr from writeBinary (its debug output): keep
  // it off the program's messages; the result is checked here.
  std::fflush(stderr);
  const int saved = dup(2), null = open("/dev/null", O_WRONLY);
  if (null >= 0) dup2(null, 2);
  const bool written = tree.writeBinary(path);
  if (saved >= 0) {
    dup2(saved, 2);
    close(saved);
  }
  if (null >= 0) close(null);
  if (!written) throw std::runtime_error("cannot write " + path);
}

}  // namespace ndtom::mapper
