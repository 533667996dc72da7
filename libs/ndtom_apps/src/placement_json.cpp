#include "ndtom_apps/placement_json.h"

namespace ndtom::apps {

void writePlacementOptions(JsonWriter& j, const PlacementOptions& o) {
  const RegistrationOptions& r = o.registration;
  j.field("method", toString(r.method));
  j.beginArray("level_factors");
  for (const int f : r.level_factors) j.field("", f);
  j.endArray();
  j.field("outlier_ratio", r.outlier_ratio);
  j.field("max_iterations", r.max_iterations);
  j.field("min_range", r.min_range);
  j.field("max_range", r.max_range);
  j.field("max_points", r.max_points);
  j.field("min_matched_fraction", r.min_matched_fraction);
  j.field("min_judged_fraction", r.min_judged_fraction);
  j.field("max_free_fraction", r.max_free_fraction);
  j.field("planar", r.planar);
  j.field("threads", r.threads);
  j.field("recovery_radius", o.recovery_radius);
  j.field("recovery_yaw_deg", o.recovery_yaw_deg);
  j.field("ground_thinning", o.ground_thinning);
  j.field("retry_without_finest", o.retry_without_finest);
  j.field("weak_direction_sigma", o.weak_direction_sigma);
}

}  // namespace ndtom::apps
