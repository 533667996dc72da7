#include "map_file.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <fstream>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom/files/map_io.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_apps/scan_source.h"

namespace ndtom::localizer {

ndtom::NdtMap loadMapFile(const std::string& path) {
  using apps::InputError;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path + ": no such map file (a .ndtom, .ndtommap or tiled map written by ndtom-map)");
  char magic[8] = {};
  std::ifstream(path, std::ios::binary).read(magic, sizeof(magic));
  try {
    if (std::string(magic, 8) == "NDTOMMAP") return ndtom::loadMap(path);
    mrpt::io::CFileGZInputStream file(path);
    mrpt_ndtom::CNDTOccupancyMap map;
    mrpt::serialization::archiveFrom(file).ReadObject(&map);
    return map.ndtMap();
  } catch (const std::exception& e) {
    throw InputError(path + ": not a readable NDT-OM (.ndtom or .ndtommap): " +
                     apps::oneLineMessage(e));
  }
}

bool isTiledMapFile(const std::string& path) {
  char magic[8] = {};
  std::ifstream(path, std::ios::binary).read(magic, sizeof(magic));
  return std::string(magic, 8) == "NDTOMTIL";
}

}  // namespace ndtom::localizer
