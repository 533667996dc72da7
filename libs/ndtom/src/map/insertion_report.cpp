#include "ndtom/map/insertion_report.h"

#include <sstream>

namespace ndtom {

InsertionReport& InsertionReport::operator+=(const InsertionReport& o) {
  points_in += o.points_in;
  hits += o.hits;
  truncated += o.truncated;
  rejected_non_finite += o.rejected_non_finite;
  rejected_too_close += o.rejected_too_close;
  rejected_out_of_grid += o.rejected_out_of_grid;
  rejected_too_far += o.rejected_too_far;
  cells_touched += o.cells_touched;
  cells_hit += o.cells_hit;
  cells_created += o.cells_created;
  gaussians_gained += o.gaussians_gained;
  gaussians_lost += o.gaussians_lost;
  rays_cast += o.rays_cast;
  voxel_visits += o.voxel_visits;
  return *this;
}

std::string InsertionReport::toString() const {
  std::ostringstream s;
  s << "points " << points_in << " (hits " << hits << ", truncated " << truncated
    << ", rejected: non-finite " << rejected_non_finite << ", too close " << rejected_too_close
    << ", outside grid " << rejected_out_of_grid << ", too far " << rejected_too_far
    << "); cells touched " << cells_touched << " (hit " << cells_hit << ", new " << cells_created
    << "); Gaussians +" << gaussians_gained << " -" << gaussians_lost << "; rays " << rays_cast
    << ", voxel visits " << voxel_visits;
  return s.str();
}

}  // namespace ndtom
