#include "ndtom/options.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace ndtom {
namespace {

[[noreturn]] void fail(const char* option, double value, const char* why) {
  std::ostringstream msg;
  msg << option << " = " << value << ": " << why;
  throw std::invalid_argument(msg.str());
}

}  // namespace

const char* toString(RayMode mode) {
  switch (mode) {
    case RayMode::PerPoint:
      return "per_point";
    case RayMode::PerHitCell:
      return "per_hit_cell";
  }
  return "unknown";
}

RayMode rayModeFromString(const std::string& text) {
  if (text == "per_point" || text == "PerPoint" || text == "0") return RayMode::PerPoint;
  if (text == "per_hit_cell" || text == "PerHitCell" || text == "1") return RayMode::PerHitCell;
  throw std::invalid_argument("ray_mode = " + text + ": expected per_point or per_hit_cell");
}

double OccupancyOptions::hitLogOdds() const {
  return std::log(p_hit / (1.0 - p_hit));
}
double OccupancyOptions::missLogOdds() const {
  return std::log(p_miss / (1.0 - p_miss));
}

void validate(const OccupancyOptions& o) {
  if (!(o.p_hit > 0.5 && o.p_hit < 1.0))
    fail("p_hit", o.p_hit, "must be in (0.5, 1): a hit is evidence of occupancy");
  if (!(o.p_miss > 0.0 && o.p_miss < 0.5))
    fail("p_miss", o.p_miss,
         "must be in (0, 0.5): a ray crossing a cell is evidence of free space");
  if (!(std::isfinite(o.logodds_min) && o.logodds_min < 0))
    fail("logodds_min", o.logodds_min, "must be finite and < 0");
  if (!(std::isfinite(o.logodds_max) && o.logodds_max > 0))
    fail("logodds_max", o.logodds_max, "must be finite and > 0");
}

void validate(const InsertOptions& o) {
  if (!(std::isfinite(o.min_range) && o.min_range >= 0))
    fail("min_range", o.min_range, "must be finite and >= 0");
  if (!(o.max_range > 0) || std::isnan(o.max_range))
    fail("max_range", o.max_range, "must be > 0 (inf for no limit)");
  if (!(o.max_range > o.min_range)) fail("max_range", o.max_range, "must be > min_range");
  static_assert(InsertOptions::kMaxThreads == 256, "the message below");
  if (!(o.threads >= 1 && o.threads <= InsertOptions::kMaxThreads))
    fail("threads", o.threads, "must be in [1, 256]");
  if (o.ray_mode != RayMode::PerPoint && o.ray_mode != RayMode::PerHitCell)
    fail("ray_mode", double(int(o.ray_mode)), "unknown ray mode");
  if (!(o.memory_budget >= kMinMemoryBudget))
    fail("memory_budget", double(o.memory_budget), "must be at least 1000000 bytes (1 MB)");
}

void validate(const Regularization& r) {
  if (!(r.min_eigen_ratio >= 0 && r.min_eigen_ratio <= 1))
    fail("min_eigen_ratio", r.min_eigen_ratio, "must be in [0, 1]");
  if (!(std::isfinite(r.min_eigen_abs) && r.min_eigen_abs >= 0))
    fail("min_eigen_abs", r.min_eigen_abs, "must be finite and >= 0");
}

void validate(const MapOptions& o) {
  if (!(o.resolution >= kMinResolution && o.resolution <= kMaxResolution))
    fail("resolution", o.resolution, "must be in [0.001, 1000] m");
  validate(o.occupancy);
  validate(o.insertion);
  validate(o.regularization);
}

}  // namespace ndtom
