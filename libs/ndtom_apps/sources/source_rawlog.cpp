// An MRPT rawlog: every supported observation (2D/3D range scan, point cloud, Velodyne) is a
// scan, at the robot pose from the log's odometry or from a trajectory file (--poses).
// The file is read twice: once to count the scans and check the poses, once to map.
#include <filesystem>
#include <sstream>

#include "mrpt_ndtom/observation_points.h"
#include "ndtom_apps/input_format.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_apps/rawlog_reader.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_apps/scan_source.h"
#include "ndtom_apps/trajectory_poses.h"

namespace ndtom::apps {
namespace {

mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& pose) {
  return mrpt::poses::CPose3D(mrpt::math::CMatrixDouble44(pose.matrix()));
}

class RawlogSource : public ScanSource {
 public:
  explicit RawlogSource(const SourceSettings& s)
      : path_(s.input),
        extraction_{s.decimation, s.decimation_3d_range},
        poses_optional_(s.poses_optional) {
    if (std::filesystem::is_directory(path_))
      throw apps::UsageError(path_ + ": a folder, not a rawlog");
    if (!s.poses_file.empty() && s.use_poses) {
      requireRegularFile("--poses", s.poses_file);
      trajectory_.emplace(s.poses_file, s.pose_format, s.pose_time_tolerance);
    }
    survey(s.max_scans);
    reader_ = std::make_unique<RawlogReader>(path_);
  }

  std::optional<Scan> next() override {
    while (yielded_ < size_) {
      auto entry = reader_->next();
      if (!entry) throw InputError(path_ + ": fewer scans than at the first reading");
      const size_t index = observation_index_++;
      const auto pose = trajectory_ ? std::optional(trajectory_->poseFor(index, entry->time))
                                    : entry->odometry_pose;
      if (!pose && !poses_optional_) {
        ++skips_.scans_without_pose;
        continue;
      }
      ++yielded_;
      Scan scan = toScan(*entry, pose ? toCPose3D(*pose) : mrpt::poses::CPose3D(), index);
      scan.pose_kind = !pose         ? Scan::PoseKind::None
                       : trajectory_ ? Scan::PoseKind::Reference
                                     : Scan::PoseKind::Odometry;
      return scan;
    }
    return std::nullopt;
  }

  std::string description() const override {
    std::ostringstream s;
    s << "rawlog " << path_ << ": " << observations_ << " scans" << limitNote(observations_, size_)
      << ", poses from "
      << (trajectory_ ? trajectory_->path() +
                            (trajectory_->matchesByTime() ? " (by time stamp)" : " (line by line)")
                      : std::string("odometry"));
    return s.str();
  }

 private:
  // First reading: counts the scans and checks that poses exist for them.
  void survey(size_t max_scans) {
    RawlogReader reader(path_);
    std::vector<double> times;
    size_t with_odometry = 0;
    while (auto entry = reader.next()) {
      times.push_back(entry->time);
      if (entry->odometry_pose) ++with_odometry;
    }
    observations_ = times.size();
    skips_.unsupported_observations = reader.unsupportedObservations();
    if (times.empty())
      throw InputError(path_ + ": no scans (2D or 3D range scans, point clouds, Velodyne scans)");
    if (trajectory_) {
      trajectory_->checkCovers(times, path_);
      size_ = limitScans(times.size(), max_scans);
    } else if (poses_optional_) {
      size_ = limitScans(times.size(), max_scans);
    } else {
      if (with_odometry == 0)
        throw InputError(path_ +
                         ": no odometry (CActionRobotMovement2D/3D, CObservationOdometry);" +
                         " give the robot's trajectory with --poses FILE");
      size_ = limitScans(with_odometry, max_scans);
    }
  }

  Scan toScan(const RawlogObservation& entry, const mrpt::poses::CPose3D& pose, size_t index) {
    Scan scan;
    scan.time = entry.time;
    scan.frame_pose = mrpt_ndtom::toIsometry(pose);
    scan.name = "observation " + std::to_string(index) + " (" +
                entry.observation->GetRuntimeClass()->className + ")";
    // The same projection for a pose given later (online mapping), by the same arithmetic.
    const auto project = [observation = entry.observation, extraction = extraction_,
                          where = path_ + ": " + scan.name](const mrpt::poses::CPose3D& at,
                                                            Scan& out) {
      try {
        auto points = mrpt_ndtom::observationPoints(*observation, at, extraction);
        out.points_world = std::move(points->points_world);
        out.sensor_origin = points->sensor_origin;
      } catch (const std::exception& e) {
        throw InputError(where + ": " + apps::oneLineMessage(e));
      }
    };
    project(pose, scan);
    scan.place_at = [project](const Eigen::Isometry3d& at, Scan& out) {
      project(toCPose3D(at), out);
    };
    return scan;
  }

  std::string path_;
  mrpt_ndtom::TPointExtractionOptions extraction_;
  bool poses_optional_;
  std::optional<TrajectoryPoses> trajectory_;
  std::unique_ptr<RawlogReader> reader_;
  size_t observations_ = 0, observation_index_ = 0, yielded_ = 0;
};

}  // namespace

std::unique_ptr<ScanSource> openRawlog(const SourceSettings& settings) {
  return std::make_unique<RawlogSource>(settings);
}

}  // namespace ndtom::apps
