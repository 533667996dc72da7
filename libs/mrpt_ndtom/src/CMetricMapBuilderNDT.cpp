// CMetricMapBuilderNDT: odometry in, observations through CNDTOnlineMapper, poses and maps out.
#include "mrpt_ndtom/CMetricMapBuilderNDT.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/system/CTicTac.h>

#include <stdexcept>

namespace mrpt_ndtom {

CMetricMapBuilderNDT::CMetricMapBuilderNDT() {
  setLoggerName("CMetricMapBuilderNDT");
  initialize();
}

CMetricMapBuilderNDT::~CMetricMapBuilderNDT() = default;

void CMetricMapBuilderNDT::initialize(const mrpt::maps::CSimpleMap& initialMap,
                                      const mrpt::poses::CPosePDF* x0) {
  std::lock_guard<std::mutex> lock(m_lock);
  // The mapper goes on from the last pose it inserted: with a map, from its last frame.
  if (x0 && !initialMap.empty())
    THROW_EXCEPTION(
        "CMetricMapBuilderNDT::initialize: x0 with an initial map is not supported (the robot "
        "goes on from the map's last frame)");
  mrpt::poses::CPose3D first_pose;
  if (!initialMap.empty()) initialMap.getAsPair(initialMap.size() - 1).pose->getMean(first_pose);
  if (x0) first_pose = mrpt::poses::CPose3D(x0->getMeanVal());
  // Built aside: if the options or the initial map are refused, nothing changes.
  std::unique_ptr<CNDTOnlineMapper> mapper;
  try {
    mapper =
        std::make_unique<CNDTOnlineMapper>(NDT_options.mapOptions, NDT_options.online, first_pose);
    for (const auto& [pose, frame] : initialMap) {
      mrpt::poses::CPose3D robot_pose;
      pose->getMean(robot_pose);
      for (const auto& obs : *frame)
        if (obs && isSupportedObservation(*obs)) mapper->insertAtPose(*obs, robot_pose);
    }
  } catch (const std::invalid_argument& e) {
    THROW_EXCEPTION(std::string("CMetricMapBuilderNDT::initialize: ") + e.what());
  }
  m_mapper = std::move(mapper);
  m_simpleMap = initialMap;
  m_steps.clear();
  m_motion.reset();
  m_lastOdometryReading.reset();
  m_metricMapStale = true;
  m_pose = mrpt::poses::CPose3DPDFGaussian(first_pose);
  if (x0) m_pose.copyFrom(*x0);
}

mrpt::poses::CPose3DPDF::Ptr CMetricMapBuilderNDT::getCurrentPoseEstimation() const {
  std::lock_guard<std::mutex> lock(m_lock);
  return std::make_shared<mrpt::poses::CPose3DPDFGaussian>(m_pose);
}

void CMetricMapBuilderNDT::processActionObservation(mrpt::obs::CActionCollection& action,
                                                    mrpt::obs::CSensoryFrame& observations) {
  std::lock_guard<std::mutex> lock(m_lock);
  if (const auto move3d = action.getActionByClass<mrpt::obs::CActionRobotMovement3D>())
    accumulateOdometry(move3d->poseChange.mean);
  else if (const auto move2d = action.getBestMovementEstimation())
    accumulateOdometry(mrpt::poses::CPose3D(move2d->poseChange->getMeanVal()));
  for (const auto& obs : observations) processObservationLocked(obs);
}

void CMetricMapBuilderNDT::processObservation(const mrpt::obs::CObservation::Ptr& obs) {
  std::lock_guard<std::mutex> lock(m_lock);
  processObservationLocked(obs);
}

void CMetricMapBuilderNDT::processObservationLocked(const mrpt::obs::CObservation::Ptr& obs) {
  ASSERTMSG_(obs, "CMetricMapBuilderNDT::processObservation: null observation");
  if (const auto odometry = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs)) {
    // Readings are poses in the odometry's own frame: the motion is between two of them.
    const mrpt::poses::CPose3D reading(odometry->odometry);
    if (m_lastOdometryReading)
      accumulateOdometry(reading - *m_lastOdometryReading);
    else if (!m_motion)
      m_motion = mrpt::poses::CPose3D();
    m_lastOdometryReading = reading;
    return;
  }
  if (!isSupportedObservation(*obs)) {
    MRPT_LOG_DEBUG_STREAM("skipping a " << obs->GetRuntimeClass()->className);
    return;
  }
  processScan(obs);
}

void CMetricMapBuilderNDT::accumulateOdometry(const mrpt::poses::CPose3D& motion) {
  m_motion = m_motion ? *m_motion + motion : motion;
}

void CMetricMapBuilderNDT::processScan(const mrpt::obs::CObservation::Ptr& obs) {
  // The map is what the robot is tracked against: without updates there is nothing to
  // track with (ndtom-localize does localization in a fixed map).
  if (!options.enableMapUpdating)
    THROW_EXCEPTION("CMetricMapBuilderNDT: enableMapUpdating = false is not supported");
  mrpt::system::CTicTac timer;
  try {
    m_pose = m_mapper->processObservation(*obs, m_motion);
  } catch (const std::invalid_argument& e) {
    THROW_EXCEPTION(std::string("CMetricMapBuilderNDT: ") + e.what());
  }
  const ndtom::OnlineStep& step = m_mapper->lastStep();
  m_steps.push_back({m_pose.mean, step.outcome, timer.Tac(),
                     step.outcome == ndtom::OnlineOutcome::Lost ? step.registration.failure : ""});
  // Motion is counted from this scan on; without odometry the mapper keeps predicting.
  if (m_motion) m_motion = mrpt::poses::CPose3D();
  if (step.inserted) {
    auto frame = mrpt::obs::CSensoryFrame::Create();
    frame->insert(obs);
    m_simpleMap.insert(std::make_shared<mrpt::poses::CPose3DPDFGaussian>(m_pose), frame);
    m_metricMapStale = true;
  }
  MRPT_LOG_DEBUG_STREAM("scan " << step.index << ": " << ndtom::toString(step.outcome) << " ("
                                << step.found_by << ") at " << m_pose.mean);
}

void CMetricMapBuilderNDT::getCurrentlyBuiltMap(mrpt::maps::CSimpleMap& out_map) const {
  std::lock_guard<std::mutex> lock(m_lock);
  out_map = m_simpleMap;
}

unsigned int CMetricMapBuilderNDT::getCurrentlyBuiltMapSize() {
  std::lock_guard<std::mutex> lock(m_lock);
  return static_cast<unsigned int>(m_simpleMap.size());
}

const mrpt::maps::CMultiMetricMap* CMetricMapBuilderNDT::getCurrentlyBuiltMetricMap() const {
  std::lock_guard<std::mutex> lock(m_lock);
  // Copied only on demand: a copy per scan would cost as much as the scan's insertion.
  if (m_metricMapStale) {
    m_metricMap.maps.clear();
    m_metricMap.maps.push_back(m_mapper->map());
    m_metricMapStale = false;
  }
  return &m_metricMap;
}

std::vector<CMetricMapBuilderNDT::TStep> CMetricMapBuilderNDT::getSteps() const {
  std::lock_guard<std::mutex> lock(m_lock);
  return m_steps;
}

}  // namespace mrpt_ndtom
