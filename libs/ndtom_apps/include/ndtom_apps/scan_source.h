// Where scans come from: one small interface over every input format. A source yields
// scans in order, each as world-frame points seen from a sensor origin.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "ndtom_apps/input_format.h"
#include "ndtom_io/pose_file.h"
#include "ndtom_io/tum_rgbd.h"

namespace ndtom::apps {

/// Bad or inconsistent input data (unreadable file, pose count mismatch, ...): the message
/// is one line naming the file.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Scan {
  std::vector<Eigen::Vector3d> points_world;                ///< (m)
  Eigen::Vector3d sensor_origin = Eigen::Vector3d::Zero();  ///< (m)
  /// The frame the points were measured in, in the world: the sensor's (PCD, TUM) or the
  /// robot's (rawlog, simplemap: the sensor's pose on the robot already applied). Identity
  /// where the input gives none (SourceSettings::poses_optional).
  Eigen::Isometry3d frame_pose = Eigen::Isometry3d::Identity();
  /// Where frame_pose comes from: a trajectory given as such (PCD poses, TUM ground truth,
  /// simplemap keyframes, --poses), the log's odometry (it drifts), or nothing.
  enum class PoseKind { Reference, Odometry, None };
  PoseKind pose_kind = PoseKind::Reference;
  double time = 0;   ///< seconds (the scan's index where the input has no time)
  std::string name;  ///< for messages: a file name or "observation 12"
  /// Sets points_world and sensor_origin to what the source yields with the frame at `pose`
  /// (a pose file naming it), by the same arithmetic: online mapping inserts its scans so,
  /// and ndtom-map --poses with its trajectory rebuilds its map bit for bit. Empty where a
  /// source cannot (placeAt() then transforms pointsInFrame()).
  std::function<void(const Eigen::Isometry3d& pose, Scan& scan)> place_at;
};

/// What a source skipped, by reason, for the summary.
struct SourceSkips {
  size_t unsupported_observations = 0;  ///< rawlog/simplemap entries that are not scans
  size_t scans_without_pose = 0;        ///< rawlog scans before the first odometry reading
  size_t frames_without_pose = 0;       ///< TUM depth images without ground truth
  size_t points_decimated = 0;          ///< dropped by decimation (not counted as rejected)
};

class ScanSource {
 public:
  virtual ~ScanSource() = default;
  /// Scans next() will yield in all (known when the source is opened).
  size_t size() const { return size_; }
  /// The next scan, or nullopt at the end. Throws InputError on unreadable data.
  virtual std::optional<Scan> next() = 0;
  /// One line: format, path, what poses are used.
  virtual std::string description() const = 0;
  SourceSkips skips() const { return skips_; }

 protected:
  // Kept by each format's source: its constructor sets the size, next() counts the skips.
  size_t size_ = 0;
  SourceSkips skips_;
};

/// Everything a source needs from the command line.
struct SourceSettings {
  std::string input;
  InputFormat format = InputFormat::Auto;
  std::string poses_file;
  ndtom::io::PoseFormat pose_format = ndtom::io::PoseFormat::Auto;
  double pose_time_tolerance = 0.02;
  ndtom::io::DepthCamera camera;
  uint32_t decimation = 1;           ///< 1 point in N of scans and clouds
  uint32_t decimation_3d_range = 1;  ///< depth images: every N-th row and column
  size_t max_scans = 0;              ///< 0 = all
  /// Points a scan may have (what the memory budget holds): readers refuse larger scans
  /// before allocating them (Default: no limit).
  uint64_t max_scan_points = UINT64_MAX;
  /// Scans without a pose are yielded in their own frame instead of being refused or
  /// skipped (localization estimates the poses): a PCD folder without poses.txt, rawlog
  /// scans without odometry.
  bool poses_optional = false;
  /// False: scans come without the input's own poses (PCD poses.txt, --poses), in their own
  /// frame; a rawlog's odometry still comes (online mapping predicts with it).
  bool use_poses = true;
};

/// One time stamp per scan from a times.txt beside PCD scans (line i: the i-th scan's time),
/// or the scan indices 0, 1, ... where `path` does not exist. Throws InputError if it is not a
/// regular file, a line is not a number, or the count is not `scans`.
std::vector<double> readScanTimes(const std::string& path, size_t scans);

/// The scan's points in its own frame (Scan::frame_pose).
std::vector<Eigen::Vector3d> pointsInFrame(const Scan& scan);
/// The scan moved to `pose`: frame_pose, points_world and sensor_origin as the source would
/// give them with that pose (Scan::place_at), else transformed from the frame.
void placeAt(Scan& scan, const Eigen::Isometry3d& pose);

/// Opens the input (detecting its format if Auto) and checks it can be read completely:
/// files exist, poses match the scans. Throws apps::UsageError or InputError.
std::unique_ptr<ScanSource> openScanSource(const SourceSettings& settings);

// One factory per format (source_*.cpp); `settings.format` is already decided.
std::unique_ptr<ScanSource> openPcdFolder(const SourceSettings& settings);
std::unique_ptr<ScanSource> openTumSequence(const SourceSettings& settings);
std::unique_ptr<ScanSource> openRawlog(const SourceSettings& settings);
std::unique_ptr<ScanSource> openSimplemap(const SourceSettings& settings);

/// Scans kept by --max-scans out of `available`.
inline size_t limitScans(size_t available, size_t max_scans) {
  return max_scans == 0 ? available : std::min(available, max_scans);
}

/// For descriptions: ", the first N mapped" when --max-scans keeps fewer than `available`.
inline std::string limitNote(size_t available, size_t used) {
  return used < available ? ", the first " + std::to_string(used) + " mapped" : std::string();
}

}  // namespace ndtom::apps
