#include "ndtom_io/scan_folder.h"

#include <algorithm>
#include <filesystem>

#include "ndtom_io/natural_order.h"

namespace fs = std::filesystem;

namespace ndtom::io {
namespace {

std::vector<std::string> pcdFilesInNaturalOrder(const std::string& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec))
    if (entry.path().extension() == ".pcd") names.push_back(entry.path().filename().string());
  if (ec) throw ScanFolderError(folder + ": cannot list the folder: " + ec.message());
  std::sort(names.begin(), names.end(), naturalLess);
  return names;
}

}  // namespace

DroppedPoints filterPoints(std::vector<Eigen::Vector3d>& points, const PointFilter& filter) {
  const size_t step = std::max<uint32_t>(filter.decimation, 1);
  DroppedPoints dropped;
  size_t kept = 0;
  for (size_t i = 0; i < points.size(); i += step) {
    const Eigen::Vector3d p = points[i];
    if ((filter.drop_non_finite && !p.allFinite()) || (filter.drop_origin && p.isZero(0.0))) {
      ++dropped.invalid;
      continue;
    }
    points[kept++] = p;
  }
  dropped.decimated = points.size() - kept - dropped.invalid;
  points.resize(kept);
  return dropped;
}

ScanFolder::ScanFolder(const std::string& folder, const ScanFolderOptions& options)
    : folder_(folder) {
  if (!fs::is_directory(folder_)) throw ScanFolderError(folder_ + ": not a folder of .pcd files");
  files_ = pcdFilesInNaturalOrder(folder_);
  if (files_.empty()) throw ScanFolderError(folder_ + ": no .pcd files");
  poses_path_ =
      options.poses_file.empty() ? (fs::path(folder_) / "poses.txt").string() : options.poses_file;
  if (!options.read_poses) return;
  if (!fs::exists(poses_path_)) {
    if (options.poses_required || !options.poses_file.empty())
      throw ScanFolderError(poses_path_ + ": no pose file");
    return;
  }
  poses_ = readPoseFile(poses_path_, options.pose_format);
  if (poses_.size() != files_.size())
    throw ScanFolderError(poses_path_ + ": " + std::to_string(poses_.size()) + " poses for " +
                          std::to_string(files_.size()) + " .pcd files in " + folder_ +
                          " (line i is the pose of the i-th scan)");
}

std::string ScanFolder::path(size_t i) const {
  return (fs::path(folder_) / files_.at(i)).string();
}

PointCloud ScanFolder::read(size_t i, const PointFilter& filter, DroppedPoints* dropped,
                            uint64_t max_points) const {
  PointCloud cloud = readPcd(path(i), max_points);
  const DroppedPoints d = filterPoints(cloud.points, filter);
  if (dropped) *dropped = d;
  return cloud;
}

}  // namespace ndtom::io
