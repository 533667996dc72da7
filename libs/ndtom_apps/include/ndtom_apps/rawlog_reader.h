// Reads an MRPT rawlog entry by entry, in either format (actions + sensory frames, or
// observations only), and keeps the robot's odometry pose along the way.
//
// Unlike CRawlog::getActionObservationPairOrObservation, which prints errors and reports them
// like the end of the file, a damaged or truncated file is an InputError here.
#pragma once

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <Eigen/Geometry>
#include <deque>
#include <memory>
#include <optional>
#include <string>

namespace ndtom::apps {

struct RawlogObservation {
  mrpt::obs::CObservation::Ptr observation;  ///< a type observationPoints() supports
  /// Robot pose from odometry: actions composed from the origin (sensory-frame format) or the
  /// latest CObservationOdometry (observation format, no interpolation); nullopt before the
  /// first action or odometry reading.
  std::optional<Eigen::Isometry3d> odometry_pose;
  double time = 0;  ///< the observation's time stamp (s, UNIX time)
};

class RawlogReader {
 public:
  /// Opens the file (plain or gzip); throws InputError if it cannot be read. Sets MRPT's
  /// path for externally stored images to the rawlog's "_Images" folder.
  explicit RawlogReader(const std::string& path);

  /// The next supported observation, or nullopt at the end of the file.
  std::optional<RawlogObservation> next();

  size_t unsupportedObservations() const { return unsupported_; }

 private:
  /// The next object in the file; nullopt at a clean end. Throws InputError otherwise.
  mrpt::serialization::CSerializable::Ptr readObject();
  void applyActions(const mrpt::serialization::CSerializable& actions);
  /// Odometry updates the pose; supported observations are queued; others are counted.
  void take(const mrpt::obs::CObservation::Ptr& obs, bool in_sensory_frame);

  std::string path_;
  std::unique_ptr<mrpt::io::CFileGZInputStream> file_;
  std::unique_ptr<mrpt::serialization::CArchive> archive_;
  size_t entries_ = 0;
  std::deque<RawlogObservation> pending_;
  mrpt::poses::CPose3D action_pose_;  ///< actions composed from the origin
  bool actions_seen_ = false;
  std::optional<Eigen::Isometry3d> odometry_;  ///< latest CObservationOdometry
  size_t unsupported_ = 0;
};

}  // namespace ndtom::apps
