#include <cstdio>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "experiments.h"

namespace ndtom::eval {

void Summary::print() const {
  std::printf("\nSummary\n");
  for (const auto& [key, value] : items_) std::printf("  %-44s %s\n", key.c_str(), value.c_str());
}

void Summary::write(const std::string& path) const {
  CsvTable table({"key", "value"});
  for (const auto& [key, value] : items_) table.addRow({key, value});
  table.write(path);
}

MapOptions recursiveNdtOptions(const EvalOptions& options, double resolution) {
  MapOptions o = ndtOmOptions(options, resolution);
  o.occupancy.enabled = false;
  return o;
}

MapOptions ndtOmOptions(const EvalOptions& options, double resolution, RayMode ray_mode) {
  MapOptions o;
  o.occupancy.logodds_min = options.clamp_min;
  o.occupancy.logodds_max = options.clamp_max;
  o.resolution = resolution;
  o.scan.ray_mode = ray_mode;
  o.scan.max_range = std::numeric_limits<double>::infinity();  // as the paper: no limit
  return o;
}

std::vector<Eigen::Vector3d> allPoints(const std::vector<Cloud>& clouds) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(totalPoints(clouds));
  for (const Cloud& c : clouds) points.insert(points.end(), c.points.begin(), c.points.end());
  return points;
}

}  // namespace ndtom::eval
