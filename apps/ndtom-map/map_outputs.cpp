#include "map_outputs.h"

#include <mrpt/io/CStream.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/serialization/CArchive.h>

#include "height_colors.h"
#include "ndtom/map_io.h"
#include "ndtom_apps/run_program.h"
#include "oblique_view.h"
#include "octomap_export.h"
#include "png_bytes.h"
#include "top_view.h"

namespace ndtom::mapper {
namespace {

// An MRPT output stream over a file sink, so that the archive goes through the same synced,
// error-naming writes as the other outputs.
class SinkStream : public mrpt::io::CStream {
 public:
  explicit SinkStream(const ndtom::FileSink& sink) : sink_(sink) {}
  size_t Write(const void* data, size_t size) override {
    sink_(data, size);
    written_ += size;
    return size;
  }
  size_t Read(void*, size_t) override { return 0; }
  uint64_t Seek(int64_t, TSeekOrigin) override { return written_; }
  uint64_t getTotalBytesCount() const override { return written_; }
  uint64_t getPosition() const override { return written_; }

 private:
  const ndtom::FileSink& sink_;
  uint64_t written_ = 0;
};

void writeMrptMap(const mrpt_ndtom::CNDTOccupancyMap& map, OutputFiles& out) {
  out.write("mrpt_map", ".ndtommap", [&](const ndtom::FileSink& sink) {
    SinkStream stream(sink);
    auto archive = mrpt::serialization::archiveFrom(stream);
    archive << map;
  });
}

void writeScene(const mrpt::opengl::CSetOfObjects::Ptr& gaussians,
                const std::vector<Eigen::Vector3d>& sensor_path, OutputFiles& out) {
  mrpt::opengl::COpenGLScene scene;
  scene.insert(gaussians);
  auto path = mrpt::opengl::CSetOfLines::Create();
  path->setName("sensor_path");
  path->setColor_u8(0, 0, 0);
  for (size_t i = 1; i < sensor_path.size(); ++i)
    path->appendLine(sensor_path[i - 1].x(), sensor_path[i - 1].y(), sensor_path[i - 1].z(),
                     sensor_path[i].x(), sensor_path[i].y(), sensor_path[i].z());
  scene.insert(path);
  const std::string file = out.stage("scene", ".3Dscene");
  bool saved = false;
  try {
    saved = scene.saveToFile(file);
  } catch (const std::exception& e) {  // MRPT's messages do not name the file
    throw std::runtime_error("cannot write " + file + ": " + apps::oneLineMessage(e));
  }
  if (!saved) throw std::runtime_error("cannot write " + file);
  ndtom::syncFile(file);  // as the outputs written here
}

}  // namespace

std::optional<CoarseMapInfo> writeMapOutputs(const mrpt_ndtom::CNDTOccupancyMap& map,
                                             const std::vector<Eigen::Vector3d>& sensor_path,
                                             const OutputSettings& settings, OutputFiles& out,
                                             StageTimes& times) {
  const ndtom::NdtMap& ndt = map.ndtMap();
  // Maps are streamed straight into their files: no copy of the encoding.
  const auto encode = [](const ndtom::NdtMap& m) {
    return [&m](const ndtom::FileSink& sink) {
      ndtom::encodeMap(m, [&](const uint8_t* data, size_t size) { sink(data, size); });
    };
  };
  times.time("map", [&] { out.write("map", ".ndtom", encode(ndt)); });
  times.time("mrpt_map", [&] { writeMrptMap(map, out); });
  // The ellipsoids once, for the scene and the picture (a mesh of ~100 bytes a triangle).
  const auto gaussians = mrpt::opengl::CSetOfObjects::Create();
  times.time("ellipsoids",
             [&] { mrpt_ndtom::buildNdtVisualization(ndt, map.renderOptions, *gaussians); });
  times.time("scene", [&] { writeScene(gaussians, sensor_path, out); });
  if (settings.pictures) {
    const HeightScale scale{map.renderOptions.color_min_z, map.renderOptions.color_max_z};
    times.time("top_view", [&] {
      out.writeBytes("top_view", ".top.png",
                     pngBytes(renderTopView(ndt, scale, sensor_path, settings.image_width)));
    });
    times.time("view_3d", [&] {
      out.writeBytes("view_3d", ".3d.png",
                     pngBytes(renderObliqueView(ndt, gaussians, map.renderOptions, sensor_path,
                                                settings.image_width)));
    });
  }
  if (settings.octomap)
    times.time("octomap", [&] { writeOctomapBinary(ndt, out.stage("octomap", ".bt")); });
  if (settings.coarse < 2) return std::nullopt;
  return times.time("coarse_map", [&] {
    const ndtom::NdtMap coarse = ndt.coarsened(settings.coarse);
    out.write("coarse_map", ".coarse" + std::to_string(settings.coarse) + ".ndtom", encode(coarse));
    return std::optional<CoarseMapInfo>(CoarseMapInfo{settings.coarse, coarse.options().resolution,
                                                      coarse.numCells(), coarse.numGaussians()});
  });
}

}  // namespace ndtom::mapper
