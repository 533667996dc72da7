// The experiments of ndtom-eval (paper Sec. IV), one file each, and what they share.
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "clouds.h"
#include "eval_options.h"
#include "ndtom/map/ndt_map.h"
#include "ndtom_apps/csv_table.h"
#include "ndtom_eval/map_similarity.h"

namespace ndtom::eval {

using apps::CsvCell;
using apps::CsvTable;

/// Headline numbers of a run: printed at the end and written to summary.csv.
class Summary {
 public:
  void add(const std::string& key, const CsvCell& value) { items_.emplace_back(key, value.text); }
  void print() const;
  void write(const std::string& path) const;

 private:
  std::vector<std::pair<std::string, std::string>> items_;
};

struct EvalContext {
  const EvalOptions& options;
  Summary& summary;
  CovarianceFloor floor;
  std::vector<std::string> files_written;

  std::string path(const std::string& file_name) const { return options.out_dir + "/" + file_name; }
  /// Full path of an output file, remembered for the final report.
  std::string output(const std::string& file_name) {
    files_written.push_back(file_name);
    return path(file_name);
  }
};

/// Recursive NDT: RCU only, no rays, no occupancy (the paper's "Recursive NDT").
MapOptions recursiveNdtOptions(const EvalOptions& o, double resolution);
/// NDT-OM with the library's default p_o 0.6, p_e 0.49 and the clamp of the options
/// (default [-2, 3.5]).
MapOptions ndtOmOptions(const EvalOptions& o, double resolution,
                        RayMode ray_mode = RayMode::PerPoint);

/// Fig. 1 (each map vs the batch map after every cloud) and Fig. 2 (every cloud vs each
/// final map) for ER, Recursive NDT and NDT-OM. `dataset` names the output files.
void runConsistency(EvalContext& ctx, const std::string& dataset, const std::vector<Cloud>& clouds,
                    double resolution);

/// Recursive NDT and NDT-OM built from all clouds at the mapping resolution.
struct MappingMaps {
  NdtMap recursive, ndtom;
  std::vector<Eigen::Vector3d> path;  ///< sensor origins
};
/// Builds the maps; with `record` also Fig. 3 (mean log-odds after every scan) and the
/// dynamic conflicts (Sec. IV-B-2).
MappingMaps runMapping(EvalContext& ctx, const std::vector<Cloud>& clouds, bool record);

/// Cells with a Gaussian in Recursive NDT that NDT-OM holds empty (log-odds <= 0).
std::vector<CellIndex> dynamicConflicts(const MappingMaps& maps);

/// Fig. 4 a-d as 3D pictures (fig4*.png).
void runFig4(EvalContext& ctx, const MappingMaps& maps);

/// Sec. IV-B-2: Gaussian counts of the fine map and of the map derived by RCU, and the check
/// of the derived map against a batch map at the coarse resolution.
void runMultiResolution(EvalContext& ctx, const std::vector<Cloud>& clouds,
                        const MappingMaps& maps);

/// Similarity to the batch map, memory and insertion time over a range of resolutions.
void runResolutionSweep(EvalContext& ctx, const std::vector<Cloud>& clouds);

/// RayMode::PerHitCell against the reference RayMode::PerPoint.
void runRayModes(EvalContext& ctx, const std::vector<Cloud>& clouds);

/// Wall-clock seconds of f().
template <class F>
double timed(F&& f);

/// Every cloud's points in one vector.
std::vector<Eigen::Vector3d> allPoints(const std::vector<Cloud>& clouds);

}  // namespace ndtom::eval

#include "ndtom_apps/process_clock.h"

template <class F>
double ndtom::eval::timed(F&& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return apps::secondsSince(start);
}
