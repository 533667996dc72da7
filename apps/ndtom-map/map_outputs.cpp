#include "map_outputs.h"

#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/serialization/CArchive.h>

#include "height_colors.h"
#include "ndtom/map_io.h"
#include "oblique_view.h"
#include "png_bytes.h"
#include "top_view.h"

namespace ndtom::mapper {
namespace {

std::string asString(const std::vector<uint8_t>& bytes) {
  return std::string(bytes.begin(), bytes.end());
}

void writeMrptMap(const mrpt_ndtom::CNDTOccupancyMap& map, OutputFiles& out) {
  const std::string path = out.stage("mrpt_map", ".ndtommap");
  mrpt::io::CFileOutputStream file;
  if (!file.open(path)) throw std::runtime_error("cannot write " + path);
  auto archive = mrpt::serialization::archiveFrom(file);
  archive << map;
}

void writeScene(const mrpt_ndtom::CNDTOccupancyMap& map,
                const std::vector<Eigen::Vector3d>& sensor_path, OutputFiles& out) {
  mrpt::opengl::COpenGLScene scene;
  auto objects = mrpt::opengl::CSetOfObjects::Create();
  mrpt_ndtom::buildNdtVisualization(map.ndtMap(), map.renderOptions, *objects);
  scene.insert(objects);
  auto path = mrpt::opengl::CSetOfLines::Create();
  path->setName("sensor_path");
  path->setColor_u8(0, 0, 0);
  for (size_t i = 1; i < sensor_path.size(); ++i)
    path->appendLine(sensor_path[i - 1].x(), sensor_path[i - 1].y(), sensor_path[i - 1].z(),
                     sensor_path[i].x(), sensor_path[i].y(), sensor_path[i].z());
  scene.insert(path);
  const std::string file = out.stage("scene", ".3Dscene");
  if (!scene.saveToFile(file)) throw std::runtime_error("cannot write " + file);
}

}  // namespace

std::optional<CoarseMapInfo> writeMapOutputs(const mrpt_ndtom::CNDTOccupancyMap& map,
                                             const std::vector<Eigen::Vector3d>& sensor_path,
                                             const OutputSettings& settings, OutputFiles& out) {
  const ndtom::NdtMap& ndt = map.ndtMap();
  out.writeBytes("map", ".ndtom", asString(ndtom::encodeMap(ndt)));
  writeMrptMap(map, out);
  writeScene(map, sensor_path, out);
  if (settings.pictures) {
    const HeightScale scale{map.renderOptions.color_min_z, map.renderOptions.color_max_z};
    out.writeBytes("top_view", ".top.png",
                   pngBytes(renderTopView(ndt, scale, sensor_path, settings.image_width)));
    out.writeBytes(
        "view_3d", ".3d.png",
        pngBytes(renderObliqueView(ndt, map.renderOptions, sensor_path, settings.image_width)));
  }
  if (settings.coarse < 2) return std::nullopt;
  const ndtom::NdtMap coarse = ndt.coarsened(settings.coarse);
  out.writeBytes("coarse_map", ".coarse" + std::to_string(settings.coarse) + ".ndtom",
                 asString(ndtom::encodeMap(coarse)));
  return CoarseMapInfo{settings.coarse, coarse.options().resolution, coarse.numCells(),
                       coarse.numGaussians()};
}

}  // namespace ndtom::mapper
