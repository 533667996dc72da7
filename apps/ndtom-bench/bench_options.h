// Command line of ndtom-bench: which data, which systems, which resolutions, where to write.
#pragma once

#include <string>
#include <vector>

namespace ndtom::bench {

/// The mapping systems the harness can run.
enum class SystemKind {
  NdtomPerPoint,    ///< NDT-OM, one ray per point (the paper's reference)
  NdtomPerHitCell,  ///< NDT-OM, one ray per hit cell
  Octomap,          ///< OctoMap 1.9.7 OcTree::insertPointCloud
  MrptGrid3d,       ///< MRPT's dense COccupancyGridMap3D
};

const char* systemName(SystemKind kind);
bool isNdtom(SystemKind kind);

/// Name given to --dataset for the generated 64-ring scan sequence.
inline constexpr const char* kSyntheticDataset = "synthetic";

struct BenchOptions {
  std::vector<std::string> datasets;  ///< directories (fullN.pcd + poses.txt) or "synthetic"
  int max_scans = 0;                  ///< scans per dataset; 0 = all (Default: all)
  std::vector<double> resolutions = {0.1, 0.2, 0.4, 0.8};  ///< m
  std::vector<SystemKind> systems = {SystemKind::NdtomPerPoint, SystemKind::NdtomPerHitCell,
                                     SystemKind::Octomap, SystemKind::MrptGrid3d};
  std::vector<int> threads;          ///< NDT-OM thread counts; empty = {1, 2} when the core has
                                     ///< ScanOptions::threads, else {1}
  double max_range = 30.0;           ///< m, the same for every system; inf: none (Default: 30 m)
  std::vector<double> real_time_ms;  ///< scan periods drawn and reported (Default: none)
  int repeats = 1;                   ///< full runs per system and resolution (Default: 1)
  int registration_scans = 20;       ///< scans registered against the map built; 0 = none
  std::string csv_path;              ///< per-run results as CSV; empty = none
  std::string plot_prefix;           ///< PNG plot per dataset: <prefix>_<dataset>.png; empty = none
  bool quiet = false;                ///< no progress on stderr
  bool help = false;
};

/// Throws apps::UsageError on an unknown option, a missing or malformed value.
BenchOptions parseArguments(int argc, const char* const argv[]);

std::string helpText(const std::string& program);

}  // namespace ndtom::bench
