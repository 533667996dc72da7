// An MRPT simplemap (.simplemap or .simplemap.gz): keyframes of (robot pose, sensory frame);
// every supported observation of a keyframe is a scan at the mean of its pose.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "mrpt_ndtom/observation_points.h"
#include "ndtom_apps/input_format.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_apps/scan_source.h"

namespace ndtom::apps {
namespace {

mrpt::maps::CSimpleMap loadSimplemap(const std::string& path) {
  if (std::filesystem::is_directory(path))
    throw apps::UsageError(path + ": a folder, not a simplemap");
  requireRegularFile("INPUT", path);
  mrpt::io::CFileGZInputStream file;
  if (!std::ifstream(path).good() || !file.open(path))
    throw InputError(path + ": cannot open the file");
  mrpt::maps::CSimpleMap map;
  try {
    auto archive = mrpt::serialization::archiveFrom(file);
    archive >> map;
  } catch (const std::exception& e) {
    throw InputError(path + ": not a readable CSimpleMap: " + apps::oneLineMessage(e));
  }
  return map;
}

class SimplemapSource : public ScanSource {
 public:
  explicit SimplemapSource(const SourceSettings& s)
      : path_(s.input), extraction_{s.decimation, s.decimation_3d_range} {
    if (!s.poses_file.empty())
      throw apps::UsageError("--poses: not used for simplemaps (their keyframes carry the poses)");
    map_ = loadSimplemap(path_);
    for (size_t k = 0; k < map_.size(); ++k) {
      const auto& [pose, frame] = map_.getAsPair(k);
      if (!pose || !frame)
        throw InputError(path_ + ": keyframe " + std::to_string(k) + " is empty");
      for (size_t o = 0; o < frame->size(); ++o) {
        if (mrpt_ndtom::isSupportedObservation(*frame->getObservationByIndex(o)))
          scans_.push_back({k, o});
        else
          ++skips_.unsupported_observations;
      }
    }
    if (scans_.empty())
      throw InputError(path_ + ": no scans (2D or 3D range scans, point clouds, Velodyne scans)");
    size_ = limitScans(scans_.size(), s.max_scans);
  }

  std::optional<Scan> next() override {
    if (index_ >= size_) return std::nullopt;
    const auto [keyframe, slot] = scans_[index_++];
    const auto& [pose_pdf, frame] = map_.getAsPair(keyframe);
    const auto obs = frame->getObservationByIndex(slot);
    Scan scan;
    scan.name =
        "keyframe " + std::to_string(keyframe) + " (" + obs->GetRuntimeClass()->className + ")";
    scan.time = mrpt::Clock::toDouble(obs->timestamp);
    scan.frame_pose = mrpt_ndtom::toIsometry(pose_pdf->getMeanVal());
    try {
      auto points = mrpt_ndtom::observationPoints(*obs, pose_pdf->getMeanVal(), extraction_);
      scan.points_world = std::move(points->points_world);
      scan.sensor_origin = points->sensor_origin;
    } catch (const std::exception& e) {
      throw InputError(path_ + ": " + scan.name + ": " + apps::oneLineMessage(e));
    }
    return scan;
  }

  std::string description() const override {
    std::ostringstream s;
    s << "simplemap " << path_ << ": " << map_.size() << " keyframes, " << scans_.size() << " scans"
      << limitNote(scans_.size(), size_);
    return s.str();
  }

 private:
  std::string path_;
  mrpt_ndtom::TPointExtractionOptions extraction_;
  mrpt::maps::CSimpleMap map_;
  std::vector<std::pair<size_t, size_t>> scans_;  ///< (keyframe, observation in its frame)
  size_t index_ = 0;
};

}  // namespace

std::unique_ptr<ScanSource> openSimplemap(const SourceSettings& settings) {
  return std::make_unique<SimplemapSource>(settings);
}

}  // namespace ndtom::apps
