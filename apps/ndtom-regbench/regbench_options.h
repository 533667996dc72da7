// Command line of ndtom-regbench: which data, which scans are held out, which initial errors,
// which systems and thread counts, where to write.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "start_plan.h"

namespace ndtom::regbench {

/// The registration systems the benchmark can run.
enum class SystemKind {
  NdtomP2D,  ///< ndtom::NdtRegistration, point to distribution
  NdtomD2D,  ///< ndtom::NdtRegistration, distribution to distribution
  MrptIcp,   ///< mrpt::slam::CICP::Align3D against a CSimplePointsMap
  PclNdt,    ///< pcl::NormalDistributionsTransform (PCL builds only)
  PclGicp,   ///< pcl::GeneralizedIterativeClosestPoint (PCL builds only)
};

const char* systemName(SystemKind kind);
/// ndtom-p2d or ndtom-d2d.
bool isNdtom(SystemKind kind);
/// Whether the system has a thread option (only NdtRegistration: PCL 1.13's NDT and GICP and
/// MRPT's ICP run on one thread).
bool usesThreads(SystemKind kind);

struct RegbenchOptions {
  std::string dataset;                       ///< folder with fullN.pcd (sensor frame), poses.txt
  std::vector<int> held_out = {15, 30, 45};  ///< scans registered; the map has all others
  int trials = 4;                            ///< starts per held-out scan and error level
  std::vector<ErrorLevel> errors = defaultErrorLevels();
  std::vector<SystemKind> systems;    ///< empty = every system this build has
  std::vector<int> threads = {1, 2};  ///< for the systems that use threads; others run once
  double resolution = 0.2;            ///< NDT-OM map cell (m)
  double max_range = 30.0;            ///< map points farther from their sensor are left out (m)
  uint32_t seed = 15;                 ///< of the initial errors' directions and signs
  std::string csv_path;               ///< one row per system, threads and error level
  std::string trials_csv_path;        ///< one row per registration
  std::string plot_path;              ///< PNG: success rate against the initial error
  bool quiet = false;                 ///< no progress on stderr
  bool help = false;
};

/// Throws apps::UsageError on an unknown option, a missing or malformed value.
RegbenchOptions parseArguments(int argc, const char* const argv[]);

std::string helpText(const std::string& program);

}  // namespace ndtom::regbench
