// A TUM RGB-D sequence folder: depth PNGs with the camera's ground-truth poses.
#include <sstream>

#include "ndtom_apps/option_values.h"
#include "ndtom_apps/scan_source.h"
#include "ndtom_io/tum_rgbd.h"

namespace ndtom::apps {
namespace {

class TumSource : public ScanSource {
 public:
  explicit TumSource(const SourceSettings& s)
      : folder_(s.input),
        camera_(s.camera),
        decimation_(s.decimation_3d_range),
        max_points_(s.max_scan_points) {
    if (!s.poses_file.empty())
      throw apps::UsageError(
          "--poses: not used for TUM RGB-D sequences (the folder's ground truth "
          "gives the poses)");
    try {
      camera_.validate();
    } catch (const std::exception& e) {
      throw apps::UsageError(std::string("TUM camera: ") + e.what());
    }
    try {
      sequence_ = ndtom::io::readTumSequence(folder_);
    } catch (const std::exception& e) {
      throw InputError(e.what());
    }
    if (sequence_.frames.empty())
      throw InputError(folder_ + ": no depth image has a ground-truth pose");
    skips_.frames_without_pose = sequence_.frames_without_pose;
    size_ = limitScans(sequence_.frames.size(), s.max_scans);
  }

  std::optional<Scan> next() override {
    if (index_ >= size_) return std::nullopt;
    const ndtom::io::TumFrame& frame = sequence_.frames[index_++];
    std::vector<Eigen::Vector3d> points;
    try {
      points =
          ndtom::io::readDepthImagePoints(frame.depth_path, camera_, int(decimation_), max_points_);
    } catch (const std::exception& e) {
      throw InputError(e.what());
    }
    Scan scan;
    scan.name = frame.depth_path;
    scan.time = frame.time;
    scan.sensor_origin = frame.camera_to_world.translation();
    scan.frame_pose = frame.camera_to_world;
    for (auto& p : points) p = frame.camera_to_world * p;  // in place: one copy of the cloud
    scan.points_world = std::move(points);
    return scan;
  }

  std::string description() const override {
    std::ostringstream s;
    s << "TUM RGB-D sequence " << folder_ << ": " << sequence_.frames.size()
      << " depth images with ground truth" << limitNote(sequence_.frames.size(), size_) << ", ";
    if (decimation_ == 1)
      s << "every pixel";
    else
      s << "every " << decimation_ << "th pixel row and column";
    return s.str();
  }

 private:
  std::string folder_;
  ndtom::io::DepthCamera camera_;
  uint32_t decimation_;
  uint64_t max_points_;
  ndtom::io::TumSequence sequence_;
  size_t index_ = 0;
};

}  // namespace

std::unique_ptr<ScanSource> openTumSequence(const SourceSettings& settings) {
  return std::make_unique<TumSource>(settings);
}

}  // namespace ndtom::apps
