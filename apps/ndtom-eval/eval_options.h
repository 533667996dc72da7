// Command line of ndtom-eval.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "ndtom_apps/motion_gate.h"

namespace ndtom::eval {

/// The experiments, by the name used on the command line.
inline const std::vector<std::string> kExperimentNames = {"consistency", "mapping",  "multires",
                                                          "sweep",       "raymodes", "fig4"};

struct EvalOptions {
  std::string tum_dir;    ///< TUM RGB-D sequence folder (associations.txt + depth/)
  std::string lidar_dir;  ///< fullN.pcd + poses.txt (KITTI convention)
  std::string out_dir = "ndtom-eval-out";
  int tum_frames = 0;               ///< first N frames; 0 = all
  int tum_decimation = 1;           ///< every k-th depth pixel in both directions (Default: 1)
  int lidar_scans = 0;              ///< first N scans for mapping/multires/sweep/raymodes; 0 = all
  int consistency_scans = 30;       ///< lidar scans for Fig. 1 and 2 (Default: 30)
  double tum_resolution = 0.1;      ///< Fig. 1/2 on TUM (Default: 0.1 m)
  double lidar_resolution = 0.2;    ///< Fig. 1/2 on lidar (Default: 0.2 m)
  double mapping_resolution = 0.3;  ///< Fig. 3, conflicts, multi-resolution (Default: 0.3 m)
  int coarsening = 3;               ///< multi-resolution factor (Default: 3, 0.3 → 0.9 m)
  std::vector<double> sweep_resolutions = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
  std::vector<double> ray_mode_resolutions = {0.2, 0.4};
  double min_eigenvalue = 1e-6;       ///< covariance floor of the similarity (Default: 1e-6 m²)
  double clamp_min = -2.0;            ///< NDT-OM log-odds clamp (Default: the library's -2)
  double clamp_max = 3.5;             ///< (Default: the library's 3.5)
  apps::MotionThresholds motion;      ///< the paper's insertion rule on the lidar scans (off)
  std::set<std::string> experiments;  ///< empty = all
  std::set<std::string> consistency_data = {"tum", "lidar"};  ///< datasets of Fig. 1 and 2
  bool help = false;

  bool runs(const std::string& experiment) const {
    return experiments.empty() || experiments.count(experiment) > 0;
  }
  /// Fig. 1 and 2 on this dataset ("tum" or "lidar")?
  bool runsConsistencyOn(const std::string& dataset) const {
    return runs("consistency") && consistency_data.count(dataset) > 0;
  }
};

/// Throws apps::UsageError with a one-line message for unknown options or bad values.
EvalOptions parseEvalOptions(int argc, char** argv);
std::string helpText();

}  // namespace ndtom::eval
