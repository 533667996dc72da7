#include "ndtom_apps/rawlog_reader.h"

#include <mrpt/img/CImage.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <fstream>

#include "mrpt_ndtom/observation_points.h"
#include "ndtom_apps/input_format.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_apps/scan_source.h"

namespace ndtom::apps {

using mrpt::obs::CObservation;

RawlogReader::RawlogReader(const std::string& path) : path_(path) {
  requireRegularFile("INPUT", path);
  if (!std::ifstream(path).good()) throw InputError(path + ": cannot open the file");
  file_ = std::make_unique<mrpt::io::CFileGZInputStream>();
  if (!file_->open(path)) throw InputError(path + ": cannot open the file");
  archive_ =
      std::make_unique<mrpt::serialization::CArchiveStreamBase<mrpt::io::CFileGZInputStream>>(
          *file_);
  mrpt::img::CImage::setImagesPathBase(mrpt::obs::CRawlog::detectImagesDirectory(path));
}

mrpt::serialization::CSerializable::Ptr RawlogReader::readObject() {
  const uint64_t before = file_->getPosition();
  try {
    auto object = archive_->ReadObject();
    ++entries_;
    return object;
  } catch (const mrpt::serialization::CExceptionEOF&) {
    if (file_->getPosition() == before) return nullptr;  // the end, between two entries
    throw InputError(path_ + ": truncated inside entry " + std::to_string(entries_ + 1));
  } catch (const std::exception& e) {
    throw InputError(path_ + ": entry " + std::to_string(entries_ + 1) +
                     " is damaged or truncated, or this is no rawlog (" + apps::oneLineMessage(e) +
                     ")");
  }
}

void RawlogReader::applyActions(const mrpt::serialization::CSerializable& object) {
  const auto& actions = dynamic_cast<const mrpt::obs::CActionCollection&>(object);
  actions_seen_ = true;
  if (const auto move2d = actions.getBestMovementEstimation()) {
    mrpt::poses::CPose2D increment;
    move2d->poseChange->getMean(increment);
    action_pose_ = action_pose_ + mrpt::poses::CPose3D(increment);
  } else if (const auto move3d = actions.getActionByClass<mrpt::obs::CActionRobotMovement3D>()) {
    action_pose_ = action_pose_ + move3d->poseChange.mean;
  }
}

void RawlogReader::take(const CObservation::Ptr& obs, bool in_sensory_frame) {
  if (const auto* odo = dynamic_cast<const mrpt::obs::CObservationOdometry*>(obs.get())) {
    odometry_ = mrpt_ndtom::toIsometry(mrpt::poses::CPose3D(odo->odometry));
    return;
  }
  if (!mrpt_ndtom::isSupportedObservation(*obs)) {
    ++unsupported_;
    return;
  }
  RawlogObservation r;
  r.observation = obs;
  r.time = mrpt::Clock::toDouble(obs->timestamp);
  // In the sensory-frame format the robot starts at the origin and moves by the actions.
  r.odometry_pose = in_sensory_frame && actions_seen_
                        ? std::optional(mrpt_ndtom::toIsometry(action_pose_))
                        : odometry_;
  pending_.push_back(std::move(r));
}

std::optional<RawlogObservation> RawlogReader::next() {
  while (pending_.empty()) {
    const auto object = readObject();
    if (!object) return std::nullopt;
    if (IS_CLASS(*object, mrpt::obs::CActionCollection)) {
      applyActions(*object);
    } else if (const auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(object)) {
      for (const auto& obs : *sf) take(obs, /*in_sensory_frame=*/true);
    } else if (const auto obs = std::dynamic_pointer_cast<CObservation>(object)) {
      take(obs, /*in_sensory_frame=*/false);
    }
  }
  RawlogObservation r = std::move(pending_.front());
  pending_.pop_front();
  return r;
}

}  // namespace ndtom::apps
