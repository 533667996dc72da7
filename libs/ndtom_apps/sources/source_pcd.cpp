// A folder of PCD scans (points in the sensor frame) with one pose per scan, KITTI's
// convention (poses.txt: line i is [R|t] of the i-th scan, sensor -> world) or a TUM
// trajectory taken line by line. Where poses are optional (localization), a folder without
// them yields the scans in their own frame, timed by times.txt (one time per line) if present.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ndtom/checked_size.h"
#include "ndtom/input_file.h"
#include "ndtom_apps/input_format.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_apps/scan_source.h"
#include "ndtom_io/natural_order.h"
#include "ndtom_io/pcd_reader.h"

namespace fs = std::filesystem;

namespace ndtom::apps {
namespace {

std::vector<std::string> pcdFilesInNaturalOrder(const std::string& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec))
    if (entry.path().extension() == ".pcd") names.push_back(entry.path().filename().string());
  if (ec) throw InputError(folder + ": cannot list the folder: " + ec.message());
  std::sort(names.begin(), names.end(), ndtom::io::naturalLess);
  return names;
}

class PcdFolderSource : public ScanSource {
 public:
  explicit PcdFolderSource(const SourceSettings& s)
      : folder_(s.input),
        decimation_(s.decimation),
        // Points are decimated after reading: a file may hold `decimation` times more.
        max_file_points_(ndtom::checkedMul(s.max_scan_points, decimation_).value_or(UINT64_MAX)) {
    if (!fs::is_directory(folder_))
      throw apps::UsageError(folder_ + ": not a folder of .pcd files");
    files_ = pcdFilesInNaturalOrder(folder_);
    if (files_.empty()) throw InputError(folder_ + ": no .pcd files");
    if (!s.poses_file.empty()) requireRegularFile("--poses", s.poses_file);
    poses_path_ = s.poses_file.empty() ? (fs::path(folder_) / "poses.txt").string() : s.poses_file;
    if (!fs::exists(poses_path_)) {
      if (!s.poses_optional || !s.poses_file.empty())
        throw InputError(poses_path_ + ": no pose file (give the scans' poses with --poses FILE)");
      poses_path_.clear();
      times_ = readScanTimes((fs::path(folder_) / "times.txt").string(), files_.size());
    } else {
      try {
        poses_ = ndtom::io::readPoseFile(poses_path_, s.pose_format);
      } catch (const std::exception& e) {
        throw InputError(e.what());
      }
      if (poses_.size() != files_.size())
        throw InputError(poses_path_ + ": " + std::to_string(poses_.size()) + " poses for " +
                         std::to_string(files_.size()) + " .pcd files in " + folder_ +
                         " (line i is the pose of the i-th scan)");
    }
    size_ = limitScans(files_.size(), s.max_scans);
  }

  std::optional<Scan> next() override {
    if (index_ >= size_) return std::nullopt;
    const std::string path = (fs::path(folder_) / files_[index_]).string();
    ndtom::io::PointCloud cloud;
    try {
      cloud = ndtom::io::readPcd(path, max_file_points_);
    } catch (const std::exception& e) {
      throw InputError(e.what());
    }
    const bool has_pose = !poses_.empty();
    const Eigen::Isometry3d sensor_to_world =
        has_pose ? poses_[index_].pose : Eigen::Isometry3d::Identity();
    Scan scan;
    scan.name = files_[index_];
    scan.time = has_pose ? poses_[index_].time : times_[index_];
    scan.frame_pose = sensor_to_world;
    scan.pose_kind = has_pose ? Scan::PoseKind::Reference : Scan::PoseKind::None;
    scan.sensor_origin = sensor_to_world * cloud.viewpoint.translation();
    // In place: a second copy of a large cloud would double the reader's memory.
    const size_t read = cloud.points.size();
    size_t kept = 0;
    for (size_t i = 0; i < read; i += decimation_)
      cloud.points[kept++] = sensor_to_world * cloud.points[i];
    cloud.points.resize(kept);
    scan.points_world = std::move(cloud.points);
    skips_.points_decimated += read - kept;
    ++index_;
    return scan;
  }

  std::string description() const override {
    std::ostringstream s;
    s << "PCD folder " << folder_ << ": " << files_.size() << " scans, "
      << (poses_path_.empty() ? std::string("no poses") : "poses from " + poses_path_);
    return s.str();
  }

 private:
  std::string folder_, poses_path_;
  uint32_t decimation_;
  uint64_t max_file_points_;
  std::vector<std::string> files_;
  std::vector<ndtom::io::StampedPose> poses_;  ///< empty: no poses
  std::vector<double> times_;                  ///< used without poses
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
