// A folder of PCD scans (points in the sensor frame) with one pose per scan, KITTI's
// convention (poses.txt: line i is [R|t] of the i-th scan, sensor -> world) or a TUM
// trajectory taken line by line. Where poses are optional (localization), a folder without
// them yields the scans in their own frame, timed by times.txt (one time per line) if present.
#include <filesystem>
#include <sstream>

#include "ndtom_internal/checked_size.h"
#include "ndtom_internal/input_file.h"
#include "ndtom_apps/input_format.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_apps/scan_source.h"
#include "ndtom_io/scan_folder.h"

namespace fs = std::filesystem;

namespace ndtom::apps {
namespace {

class PcdFolderSource : public ScanSource {
 public:
  explicit PcdFolderSource(const SourceSettings& s)
      : filter_{s.decimation},
        // Points are decimated after reading: a file may hold `decimation` times more.
        max_file_points_(ndtom::checkedMul(s.max_scan_points, s.decimation).value_or(UINT64_MAX)) {
    if (!fs::is_directory(s.input)) throw UsageError(s.input + ": not a folder of .pcd files");
    if (!s.poses_file.empty()) requireRegularFile("--poses", s.poses_file);
    ndtom::io::ScanFolderOptions options;
    options.poses_file = s.poses_file;
    options.pose_format = s.pose_format;
    options.poses_required = false;  // said below, with the option that gives them
    options.read_poses = s.use_poses;
    try {
      folder_.emplace(s.input, options);
    } catch (const std::exception& e) {
      throw InputError(e.what());
    }
    if (!folder_->hasPoses()) {
      if (!s.poses_optional)
        throw InputError(folder_->posesPath() +
                         ": no pose file (give the scans' poses with --poses FILE)");
      times_ = readScanTimes((fs::path(s.input) / "times.txt").string(), folder_->size());
    }
    size_ = limitScans(folder_->size(), s.max_scans);
  }

  std::optional<Scan> next() override {
    if (index_ >= size_) return std::nullopt;
    ndtom::io::PointCloud cloud;
    ndtom::io::DroppedPoints dropped;
    try {
      cloud = folder_->read(index_, filter_, &dropped, max_file_points_);
    } catch (const std::exception& e) {
      throw InputError(e.what());
    }
    const bool has_pose = folder_->hasPoses();
    const Eigen::Isometry3d sensor_to_world =
        has_pose ? folder_->poses()[index_].pose : Eigen::Isometry3d::Identity();
    Scan scan;
    scan.name = folder_->fileName(index_);
    scan.time = has_pose ? folder_->poses()[index_].time : times_[index_];
    scan.frame_pose = sensor_to_world;
    scan.pose_kind = has_pose ? Scan::PoseKind::Reference : Scan::PoseKind::None;
    scan.sensor_origin = sensor_to_world * cloud.viewpoint.translation();
    if (!has_pose) {  // placed later (online mapping): the frame's points are kept for it
      const Eigen::Vector3d origin = cloud.viewpoint.translation();
      scan.place_at = [sensor = cloud.points, origin](const Eigen::Isometry3d& pose, Scan& out) {
        out.sensor_origin = pose * origin;
        out.points_world.resize(sensor.size());
        for (size_t i = 0; i < sensor.size(); ++i) out.points_world[i] = pose * sensor[i];
      };
    }
    // In place: a second copy of a large cloud would double the reader's memory.
    for (Eigen::Vector3d& p : cloud.points) p = sensor_to_world * p;
    scan.points_world = std::move(cloud.points);
    skips_.points_decimated += dropped.decimated;
    ++index_;
    return scan;
  }

  std::string description() const override {
    std::ostringstream s;
    s << "PCD folder " << folder_->folder() << ": " << folder_->size() << " scans, "
      << (folder_->hasPoses() ? "poses from " + folder_->posesPath() : std::string("no poses"));
    return s.str();
  }

 private:
  ndtom::io::PointFilter filter_;  ///< decimation only: the map rejects invalid points itself
  uint64_t max_file_points_;
  std::optional<ndtom::io::ScanFolder> folder_;
  std::vector<double> times_;  ///< used without poses
  size_t index_ = 0;
};

}  // namespace

std::vector<double> readScanTimes(const std::string& path, size_t scans) {
  std::vector<double> times;
  if (!fs::exists(path)) {
    for (size_t i = 0; i < scans; ++i) times.push_back(double(i));
    return times;
  }
  // A line of at most ~40 bytes per scan: 64 MB is over a million scans.
  constexpr uint64_t kMaxTimesFileBytes = uint64_t(64) << 20;
  std::istringstream in;
  try {
    in.str(ndtom::readInputFile(path, kMaxTimesFileBytes, "time stamp file"));
  } catch (const ndtom::InputFileError& e) {
    throw InputError(e.what());
  }
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    line = apps::trim(line);
    if (line.empty() || line[0] == '#') continue;
    try {
      times.push_back(apps::parseReal(path, line));
    } catch (const std::exception&) {
      throw InputError(path + ":" + std::to_string(number) + ": not a time stamp: '" + line + "'");
    }
  }
  if (times.size() != scans)
    throw InputError(path + ": " + std::to_string(times.size()) + " time stamps for " +
                     std::to_string(scans) + " .pcd files (line i is the time of the i-th scan)");
  return times;
}

std::unique_ptr<ScanSource> openPcdFolder(const SourceSettings& settings) {
  return std::make_unique<PcdFolderSource>(settings);
}

}  // namespace ndtom::apps
