#include "ndtom_apps/map_outputs.h"

#include <mrpt/io/CStream.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/serialization/CArchive.h>

#include <future>

#include "mrpt_ndtom/encoded_archive.h"
#include "ndtom/files/map_io.h"
#include "ndtom/files/tiled_map_io.h"
#include "ndtom_apps/gzip_members.h"
#include "ndtom_apps/height_colors.h"
#include "ndtom_apps/oblique_view.h"
#include "ndtom_apps/octomap_export.h"
#include "ndtom_apps/png_bytes.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_apps/top_view.h"

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

// An MRPT archive straight into the scene's compressor. The archive writes a mesh a float at
// a time: no stream and no std::function between it and the compressor's buffer.
class GzipArchive final : public mrpt::serialization::CArchive {
 public:
  explicit GzipArchive(GzipMemberWriter& gzip) : gzip_(gzip) {}

 protected:
  size_t write(const void* data, size_t size) override {
    gzip_.write(data, size);
    return size;
  }
  size_t read(void*, size_t) override { return 0; }

 private:
  GzipMemberWriter& gzip_;
};

// `encoded`: the map's encoding, written to the .ndtom already (the archive holds the same).
void writeMrptMap(const mrpt_ndtom::CNDTOccupancyMap& map, const std::vector<uint8_t>& encoded,
                  const std::string& file) {
  ndtom::writeFileSynced(file, [&](const ndtom::FileSink& sink) {
    SinkStream stream(sink);
    auto archive = mrpt::serialization::archiveFrom(stream);
    mrpt_ndtom::writeWithEncodedMap(archive, map, encoded);
  });
}

void writeBytes(const std::string& file, const std::string& bytes) {
  ndtom::writeFileSynced(file, [&](const ndtom::FileSink& sink) { sink(bytes.data(), bytes.size()); });
}

// What COpenGLScene::saveToFile writes (the scene in an MRPT archive, gzip), but compressed
// while it is serialised, on `threads` threads, by libdeflate at its fastest level: deflate
// took most of its time.
void writeScene(const mrpt::opengl::CSetOfObjects::Ptr& gaussians,
                const std::vector<Eigen::Vector3d>& sensor_path, const std::string& file,
                int threads) {
  mrpt::opengl::COpenGLScene scene;
  scene.insert(gaussians);
  auto path = mrpt::opengl::CSetOfLines::Create();
  path->setName("sensor_path");
  path->setColor_u8(0, 0, 0);
  for (size_t i = 1; i < sensor_path.size(); ++i)
    path->appendLine(sensor_path[i - 1].x(), sensor_path[i - 1].y(), sensor_path[i - 1].z(),
                     sensor_path[i].x(), sensor_path[i].y(), sensor_path[i].z());
  scene.insert(path);
  ndtom::writeFileSynced(file, [&](const ndtom::FileSink& sink) {
    GzipMemberWriter gzip(sink, 1, threads);
    GzipArchive(gzip) << scene;
    gzip.finish();
  });
}


}  // namespace

std::optional<CoarseMapInfo> writeMapOutputs(const mrpt_ndtom::CNDTOccupancyMap& map,
                                             const std::vector<Eigen::Vector3d>& sensor_path,
                                             const OutputSettings& settings, apps::OutputFiles& out,
                                             apps::StageTimes& times) {
  const ndtom::NdtMap& ndt = map.ndtMap();
  // Staged here in a fixed order, written by two lanes in parallel.
  const std::string map_file = out.stage("map", ".ndtom");
  const std::string mrpt_file = out.stage("mrpt_map", ".ndtommap");
  const std::string scene_file = out.stage("scene", ".3Dscene");
  const std::string top_file = settings.pictures ? out.stage("top_view", ".top.png") : "";
  const std::string view_file = settings.pictures ? out.stage("view_3d", ".3d.png") : "";
  const std::string octomap_file = settings.octomap ? out.stage("octomap", ".bt") : "";
  const std::string tiles_file =
      settings.tile_blocks > 0 ? out.stage("tiled_map", ".ndtomtiles") : "";
  const bool coarse = settings.coarse >= 2;
  const std::string coarse_file =
      coarse ? out.stage("coarse_map", ".coarse" + std::to_string(settings.coarse) + ".ndtom")
             : "";

  // Maps are streamed straight into their files: no copy of the encoding.
  const auto writeMap = [](const ndtom::NdtMap& m, const std::string& file) {
    ndtom::writeFileSynced(file, [&m](const ndtom::FileSink& sink) {
      ndtom::encodeMap(m, [&](const uint8_t* data, size_t size) { sink(data, size); });
    });
  };
  // The Gaussians selected and coloured once, for the scene and the picture: in the scene's
  // lane, while this one encodes the map; the 3D picture waits for them.
  std::vector<mrpt_ndtom::DrawnGaussian> drawn;
  std::promise<void> drawn_promise;
  std::shared_future<void> drawn_ready = drawn_promise.get_future().share();

  // The scene's mesh (~100 bytes a triangle) lives only in this lane.
  apps::StageTimes scene_times(times.origin());
  const auto writeSceneLane = [&] {
    try {
      scene_times.time("ellipsoids",
                       [&] { drawn = mrpt_ndtom::drawnGaussians(ndt, map.renderOptions); });
      drawn_promise.set_value();
    } catch (...) {
      drawn_promise.set_exception(std::current_exception());
      throw;
    }
    const auto gaussians = mrpt::opengl::CSetOfObjects::Create();
    scene_times.time("scene", [&] {
      mrpt_ndtom::buildNdtVisualization(ndt, drawn, map.renderOptions, *gaussians);
      writeScene(gaussians, sensor_path, scene_file, settings.threads);
    });
  };
  std::future<void> scene_lane;
  if (settings.threads > 1)
    scene_lane = std::async(std::launch::async, writeSceneLane);
  else
    writeSceneLane();

  std::optional<CoarseMapInfo> coarse_info;
  try {
    // Encoded once for the .ndtom and the .ndtommap (the same bytes in both).
    std::vector<uint8_t> encoded;
    times.time("map", [&] {
      encoded = ndtom::encodeMap(ndt);
      ndtom::writeFileSynced(map_file, [&](const ndtom::FileSink& sink) {
        sink(encoded.data(), encoded.size());
      });
    });
    times.time("mrpt_map", [&] { writeMrptMap(map, encoded, mrpt_file); });
    if (settings.pictures) {
      const apps::HeightScale scale{map.renderOptions.color_min_z, map.renderOptions.color_max_z};
      times.time("top_view", [&] {
        writeBytes(top_file, apps::pngBytes(apps::renderTopView(ndt, scale, sensor_path,
                                                                settings.image_width)));
      });
      drawn_ready.get();  // rethrows the scene lane's error in selecting them
      times.time("view_3d", [&] {
        writeBytes(view_file,
                   apps::pngBytes(apps::renderObliqueView(ndt, drawn, map.renderOptions,
                                                          sensor_path, settings.image_width)));
      });
    }
    if (settings.octomap) times.time("octomap", [&] { writeOctomapBinary(ndt, octomap_file); });
    if (settings.tile_blocks > 0)
      times.time("tiled_map", [&] { ndtom::saveTiledMap(ndt, tiles_file, settings.tile_blocks); });
    if (coarse)
      times.time("coarse_map", [&] {
        const ndtom::NdtMap coarser = ndt.coarsened(settings.coarse);
        writeMap(coarser, coarse_file);
        coarse_info = CoarseMapInfo{settings.coarse, coarser.options().resolution,
                                    coarser.numCells(), coarser.numGaussians()};
      });
  } catch (...) {
    if (scene_lane.valid()) scene_lane.wait();  // it uses what this frame holds
    throw;
  }
  if (scene_lane.valid()) scene_lane.get();  // its error, if any
  times.merge(scene_times);
  return coarse_info;
}

}  // namespace ndtom::mapper
