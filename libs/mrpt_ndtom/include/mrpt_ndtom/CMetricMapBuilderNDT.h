// Online NDT-OM as an MRPT map builder, swappable with mrpt::slam::CMetricMapBuilderICP
// (icp-slam's) wherever a CMetricMapBuilder is used:
//
//   CMetricMapBuilderNDT builder;
//   builder.NDT_options.loadFromConfigFile(ini, "NDTSLAM");
//   builder.initialize();
//   builder.processActionObservation(action, frame);   // or processObservation(obs)
//   builder.getCurrentPoseEstimation(); builder.getCurrentlyBuiltMetricMap();
//
// Each observation is registered against the NDT-OM built so far and inserted at the pose
// found (CNDTOnlineMapper); odometry, from the actions or CObservationOdometry, only improves
// the prediction. Unlike icp-slam every observation is registered and inserted: there are
// no distance thresholds. An observation nothing places is "lost": its pose is the
// prediction and it is not inserted. Observations of other types (images, IMU, ...) are
// skipped. options.enableMapUpdating = false is refused: the map is what the robot is
// tracked against.
//
// Configuration (.ini, MRPT's style), for section S:
//   [S]                             online mapper: registration, recovery, target
//   [S_ndtOccupancyMap_00_insertOpts]  the map (CNDTOccupancyMap::TInsertionOptions)
// the names CMultiMetricMap would give the built map's section.
//
// Threading: the public methods may be called from several threads (one lock).
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/slam/CMetricMapBuilder.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "mrpt_ndtom/CNDTOnlineMapper.h"
#include "ndtom/online/online_mapper.h"

namespace mrpt_ndtom {

class CMetricMapBuilderNDT : public mrpt::slam::CMetricMapBuilder {
 public:
  /// The builder's options as .ini sections (see the top of this file).
  class TConfigParams : public mrpt::config::CLoadableOptions {
   public:
    /// Throws MRPT's exception naming the section and key of a bad value; a key that is
    /// absent keeps the current value.
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;
    void dumpToTextStream(std::ostream& out) const override;

    /// The section holding the map's options for the builder's `section`.
    static std::string mapSection(const std::string& section);
    /// The keys of the builder's own section (for programs that refuse unknown keys).
    static std::vector<std::string> keys();

    /// The map built (resolution, occupancy, ranges, decimation, ...).
    CNDTOccupancyMap::TInsertionOptions mapOptions;
    /// Registration (its `planar` for 2D scans), recovery and the registration target; its
    /// `map` is not used: mapOptions is.
    ndtom::OnlineMapperOptions online;

    bool operator==(const TConfigParams& o) const;
  };
  TConfigParams NDT_options;

  /// Ready to map with default options; call initialize() after changing NDT_options.
  CMetricMapBuilderNDT();
  ~CMetricMapBuilderNDT() override;

  /// Starts over with NDT_options: the frames of `initialMap` inserted at their poses (not
  /// registered; later observations must not be older), the robot at its last frame's pose,
  /// or at `x0` when there is no initial map, else at the origin. Throws (naming the option)
  /// if NDT_options are invalid, and for x0 with an initial map.
  void initialize(const mrpt::maps::CSimpleMap& initialMap = mrpt::maps::CSimpleMap(),
                  const mrpt::poses::CPosePDF* x0 = nullptr) override;

  /// The robot's last pose, with the registration's covariance (a CPose3DPDFGaussian).
  mrpt::poses::CPose3DPDF::Ptr getCurrentPoseEstimation() const override;

  /// The action's odometry (CActionRobotMovement2D or 3D) predicts the motion, then each
  /// observation of the frame is processed.
  void processActionObservation(mrpt::obs::CActionCollection& action,
                                mrpt::obs::CSensoryFrame& observations) override;
  /// One observation of an observation-only rawlog: CObservationOdometry predicts the
  /// motion; a scan or cloud is registered and inserted; other types are skipped.
  void processObservation(const mrpt::obs::CObservation::Ptr& obs);

  /// The inserted observations with their poses (initialize()'s included).
  void getCurrentlyBuiltMap(mrpt::maps::CSimpleMap& out_map) const override;
  unsigned int getCurrentlyBuiltMapSize() override;
  /// A CMultiMetricMap holding the NDT-OM built so far (a CNDTOccupancyMap), copied from the
  /// mapper when it changed since the last call; valid until the next change.
  const mrpt::maps::CMultiMetricMap* getCurrentlyBuiltMetricMap() const override;

  /// A top view of the map's occupied Gaussians (black) and the robot's path (red), 2 pixels
  /// per cell edge, at most 4000 pixels a side; the format follows the file's extension (.png,
  /// .bmp, ...), whatever `formatEMF_BMP` says (EMF is Windows-only).
  void saveCurrentEstimationToImage(const std::string& file, bool formatEMF_BMP = true) override;

  /// One per scan or cloud processed since initialize(): the robot's pose and how it was found.
  struct TStep {
    mrpt::poses::CPose3D pose;
    ndtom::OnlineOutcome outcome = ndtom::OnlineOutcome::Lost;
    double seconds = 0;    ///< registration, retries, search and insertion
    std::string why_lost;  ///< the registration's failure, for a lost scan
  };
  std::vector<TStep> getSteps() const;

 private:
  void processObservationLocked(const mrpt::obs::CObservation::Ptr& obs);
  void accumulateOdometry(const mrpt::poses::CPose3D& motion);
  void processScan(const mrpt::obs::CObservation::Ptr& obs);

  mutable std::mutex m_lock;
  std::unique_ptr<CNDTOnlineMapper> m_mapper;
  mrpt::maps::CSimpleMap m_simpleMap;
  mrpt::poses::CPose3DPDFGaussian m_pose;
  std::vector<TStep> m_steps;
  /// The robot's motion since the last scan, once any odometry was seen (else the mapper
  /// predicts with constant velocity).
  std::optional<mrpt::poses::CPose3D> m_motion;
  std::optional<mrpt::poses::CPose3D> m_lastOdometryReading;  ///< CObservationOdometry's
  mutable mrpt::maps::CMultiMetricMap m_metricMap;
  mutable bool m_metricMapStale = true;
};

}  // namespace mrpt_ndtom
