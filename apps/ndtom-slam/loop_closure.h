// Loop closure for ndtom-slam: keyframes with their submaps, loop candidates checked both
// ways, and the pose graph on MRPT's optimizer. Odometry runs against a live map of the last
// few keyframes' submaps, so it never registers against its own drifted past; the graph
// corrects the keyframes, and each scan follows its keyframe. When a loop closes, the live
// window is moved to where the graph puts its newest keyframe (its scans inserted again there)
// and odometry goes on in the graph's frame: the pose known during the run is the corrected one.
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ndtom/online/online_mapper.h"
#include "ndtom/slam/keyframes.h"
#include "ndtom/slam/loop_candidates.h"
#include "ndtom/slam/loop_check.h"
#include "pose_graph.h"

namespace ndtom::slam {

struct LoopClosureOptions {
  /// Off by default until odometry against a window of keyframes is as robust as against the
  /// whole map (doc/slam.md, "Not yet done (loop closure)").
  bool enabled = false;
  KeyframeOptions keyframes;
  LoopSearchOptions search;
  LoopCheckOptions check;
  /// Keyframes whose submaps make the live map, the current one included (Default: 3: the
  /// two finished before it, a copy and a merge of 0.1-0.2 s at each keyframe; 6 took 0.4 s).
  size_t window = 3;
  /// After this many lost scans in a row odometry starts again: the scan is inserted at its
  /// prediction and starts a keyframe, joined to the last by an edge of `restart_sigma_m`
  /// and `restart_sigma_deg` (Default: 10; 2 m, 10°), so that a loop may correct it. Without
  /// it a live map of a few keyframes that once loses the robot never finds it again.
  int restart_after_lost = 10;
  double restart_sigma_m = 2, restart_sigma_deg = 10;
  /// Odometry edges: σ of translation (m) and rotation (degrees), a constant plus a part per
  /// metre between the keyframes, added to the scans' registration covariances (which treat
  /// points as independent and alone would trust odometry over any loop).
  /// Rotation is tight: the walls hold odometry's heading (city: no heading drift over
  /// 2 km); with 0.3° an edge the graph bent whole streets to close a loop.
  double odometry_sigma_m = 0.01, odometry_sigma_m_per_m = 0.005;
  double odometry_sigma_deg = 0.02, odometry_sigma_deg_per_m = 0.002;
  /// Added to an edge whose keyframe holds a scan recovered by a search (Default: 0.5 m, 2°).
  double recovered_sigma_m = 0.5, recovered_sigma_deg = 2;
};

/// Throws std::invalid_argument naming the bad option.
void validate(const LoopClosureOptions& options);

struct LoopRecord {
  size_t older = 0, newer = 0;  ///< keyframes
  LoopCheck check;              ///< without its registrations' level reports
};

struct LoopClosureReport {
  std::vector<Eigen::Isometry3d> anchors_odometry;  ///< keyframes before optimization
  std::vector<Eigen::Isometry3d> anchors_optimized;
  std::vector<size_t> keyframe_first_scan;
  std::vector<LoopRecord> loops;  ///< every candidate checked
  size_t accepted = 0, rejected = 0, optimizations = 0;
  size_t restarts = 0;  ///< odometry started again after lost scans
  size_t live_corrections = 0;  ///< the live window moved to the graph's poses
  GraphOptimization last_optimization;
  double check_seconds = 0, optimize_seconds = 0, window_seconds = 0;
  double correction_seconds = 0;  ///< moving the live window after loop closures
  std::string graph_text;  ///< MRPT's text format
};

class LoopClosure {
 public:
  /// Throws std::invalid_argument on bad options.
  LoopClosure(const LoopClosureOptions& options, const MapOptions& map, int threads);
  /// Commits `step` to `mapper` (its live map first replaced by the window when the scan starts
  /// a keyframe), adds the scan to its keyframe, and checks loops for a keyframe just finished.
  void commit(OnlineMapper& mapper, OnlineStep& step,
              const std::vector<Eigen::Vector3d>& points_sensor,
              const std::vector<Eigen::Vector3d>& points_map, const Eigen::Vector3d& origin_map);
  /// Checks the last keyframe and optimizes a final time.
  void finish();
  /// Scan `index`'s pose after optimization.
  Eigen::Isometry3d optimizedPose(size_t index) const;
  /// A pose of the live frame (where odometry is now) in odometry's own, uncorrected frame:
  /// the trajectory had no loop ever closed.
  Eigen::Isometry3d odometryPose(const Eigen::Isometry3d& live) const {
    return live_from_odometry_.inverse() * live;
  }
  const LoopClosureReport& report() const { return report_; }

 private:
  /// Returns the frame change where a loop closed (the live frame moved).
  std::optional<Eigen::Isometry3d> startKeyframe(OnlineMapper& mapper, OnlineStep& step,
                                  const std::vector<Eigen::Vector3d>& points_sensor, bool restart);
  void finishScan(OnlineMapper& mapper, OnlineStep& step,
                  const std::vector<Eigen::Vector3d>& points_map, const Eigen::Vector3d& origin_map,
                  bool restart);
  Eigen::Isometry3d moveWindow(size_t new_keyframe);
  void addOdometryEdge(size_t newer, const Eigen::Isometry3d& relative, bool restart);
  /// Whether a loop closed (and the graph was optimized).
  bool checkLoops(size_t keyframe);
  bool checkLoop(size_t older, size_t current, const Keyframe& newer, double radius);
  void coarsen(Keyframe& keyframe) const;
  void optimize();
  NdtMap window() const;

  LoopClosureOptions options_;
  MapOptions map_options_;
  ScanOptions scan_options_;  ///< the map's, on the run's threads: submaps' insertions
  LoopChecker checker_;
  PoseGraph graph_;
  std::vector<Keyframe> keyframes_;
  std::vector<size_t> scan_keyframe_;
  std::vector<Eigen::Isometry3d> scan_odometry_;
  Matrix6d segment_covariance_ = Matrix6d::Zero();  ///< scans' registrations since the anchor
  double path_ = 0, path_at_closure_ = 0;
  int lost_in_a_row_ = 0;
  Eigen::Isometry3d live_from_odometry_ = Eigen::Isometry3d::Identity();
  /// The scans of the keyframes in the live window, as inserted into their submaps (map frame):
  /// a correction inserts them again, moved.
  struct InsertedScan {
    std::vector<Eigen::Vector3d> points;
    Eigen::Vector3d origin;
  };
  std::map<size_t, std::vector<InsertedScan>> window_scans_;
  LoopClosureReport report_;
};

}  // namespace ndtom::slam
