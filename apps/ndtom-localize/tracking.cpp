#include "tracking.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "ndtom/localization/motion_prediction.h"
#include "ndtom_apps/process_clock.h"
#include "ndtom_apps/process_memory.h"

namespace ndtom::localizer {
namespace {

using Clock = std::chrono::steady_clock;
using PoseKind = apps::Scan::PoseKind;

Outcome outcomeOf(ndtom::PlacementOutcome outcome) {
  switch (outcome) {
    case ndtom::PlacementOutcome::Tracked:
      return Outcome::Tracked;
    case ndtom::PlacementOutcome::Recovered:
      return Outcome::Recovered;
    case ndtom::PlacementOutcome::Lost:
      break;
  }
  return Outcome::Lost;
}

class Tracker {
 public:
  Tracker(const ndtom::NdtMap& map, const TrackingSettings& settings)
      : map_(map),
        settings_(settings),
        placer_(settings.placement),
        motion_(settings.initial.value_or(Eigen::Isometry3d::Identity())),
        localized_(settings.initial.has_value()) {
    if (settings.live.enabled) live_.emplace(map.options(), settings.live);
  }

  void localize(const apps::Scan& scan, ScanRecord& record, TrackingResult& totals) {
    const std::vector<Eigen::Vector3d> points = apps::pointsInFrame(scan);
    record.points = points.size();
    bool search_everywhere =
        !localized_ || settings_.global_every_scan ||
        (settings_.relocalize_after > 0 && lost_in_a_row_ >= settings_.relocalize_after);
    if (!search_everywhere) {
      record.prediction = predict(scan);
      if (settings_.prepare_map) settings_.prepare_map(record.prediction->translation());
      track(targetFor(*record.prediction), points, record);
    }
    if (unconfirmed_) {
      unconfirmed_ = false;
      if (record.outcome == Outcome::Lost) {
        withdraw(totals.scans.back(), "the next scan could not be tracked from it");
        search_everywhere = true;  // this scan searched for at once
      }
    }
    if (record.outcome == Outcome::Lost && search_everywhere) {
      if (settings_.prepare_map) settings_.prepare_map(std::nullopt);
      ++totals.global_searches;
      relocalize(points, record);
    }
    if (record.outcome == Outcome::Lost) {
      ++lost_in_a_row_;
      record.pose = record.prediction;
    } else {
      lost_in_a_row_ = 0;
    }
    // A pose found by a whole-map search stands once the next scan tracks from it: alone,
    // a look-alike place (another city's street) can pass every check of one scan.
    unconfirmed_ = record.outcome == Outcome::Relocalized && !settings_.global_every_scan;
    if (live_ && record.outcome != Outcome::Lost && !unconfirmed_) extendLiveMap(scan, record);
    if (record.pose) {
      if (record.outcome == Outcome::Relocalized)
        motion_ = ConstantVelocity(*record.pose);  // the velocity before is unknown
      motion_.update(*record.pose, scan.time);
    }
    if (scan.pose_kind == PoseKind::Odometry) {
      last_odometry_ = scan.frame_pose;
      totals.odometry_used = true;
    }
  }

 private:
  Eigen::Isometry3d predict(const apps::Scan& scan) const {
    if (scan.pose_kind == PoseKind::Odometry && last_odometry_)
      return motion_.lastPose() * (last_odometry_->inverse() * scan.frame_pose);
    return motion_.predict(scan.time);
  }

  /// The prior map with the live one around `prediction`; the prior map alone where nothing
  /// of either is near (then the registration says how far off the scan is).
  const ndtom::NdtMap& targetFor(const Eigen::Isometry3d& prediction) {
    if (!live_) return map_;
    const ndtom::NdtMap& target = live_->targetAround(map_, prediction);
    return target.numGaussians() > 0 ? target : map_;
  }

  /// The scan at its pose into the live map, and which map(s) its points land in.
  void extendLiveMap(const apps::Scan& scan, ScanRecord& record) {
    apps::Scan placed = scan;
    apps::placeAt(placed, *record.pose);
    const LiveMap::Shares shares = live_->sharesOf(map_, placed.points_world);
    record.in_prior = shares.prior;
    record.in_live = shares.live;
    live_->insert(placed.points_world, placed.sensor_origin);
  }

 public:
  std::optional<ndtom::NdtMap> extendedMap() const {
    if (!live_ || !settings_.live.keep_all) return std::nullopt;
    return live_->extended(map_);
  }

 private:
  // `map`: the prior map, or with the live map's cells where the prior has none.
  void track(const ndtom::NdtMap& map, const std::vector<Eigen::Vector3d>& points,
             ScanRecord& record) {
    ndtom::Placement placed = placer_.place(map, points, *record.prediction, motion_.lastPose());
    record.outcome = outcomeOf(placed.outcome);
    record.found_by = placed.found_by;
    record.registrations += placed.registrations;
    record.weak_directions = placed.weak_directions;
    record.result = std::move(placed.registration);
    if (record.outcome != Outcome::Lost) record.pose = placed.pose;
  }

  void relocalize(const std::vector<Eigen::Vector3d>& points, ScanRecord& record) {
    ndtom::GlobalLocalizationResult search;
    try {
      search = placer_.localizer().localize(map_, points);
    } catch (const std::invalid_argument& e) {
      record.result.failure = e.what();
      return;
    }
    record.registrations += int(search.refined + search.fully_refined);
    if (!search.found) {
      record.result.failure = "global localization: " + search.failure;
      return;
    }
    record.result = search.best;
    accept(record, Outcome::Relocalized, "global search");
    localized_ = true;
  }

  /// A relocalized scan whose pose the next scan did not confirm: lost, saying why.
  static void withdraw(ScanRecord& record, const std::string& why) {
    record.outcome = Outcome::Lost;
    record.found_by.clear();
    record.pose = record.prediction;
    const Eigen::Vector3d t = record.result.pose.translation();
    char at[96];
    std::snprintf(at, sizeof at, "(%.2f, %.2f, %.2f)", t.x(), t.y(), t.z());
    record.result.failure =
        std::string("global localization: the pose found at ") + at + " was not confirmed: " + why;
  }

 public:
  /// After the last scan: a relocalization no scan could confirm is withdrawn.
  void finish(TrackingResult& totals) {
    if (unconfirmed_) withdraw(totals.scans.back(), "no scan came after it");
    unconfirmed_ = false;
  }

 private:
  void accept(ScanRecord& record, Outcome outcome, const std::string& found_by) {
    record.outcome = outcome;
    record.found_by = found_by;
    record.pose = record.result.pose;
  }

  const ndtom::NdtMap& map_;
  const TrackingSettings& settings_;
  ndtom::ScanPlacer placer_;  // holds the registration (and its pyramid) for all uses
  ConstantVelocity motion_;
  std::optional<LiveMap> live_;
  std::optional<Eigen::Isometry3d> last_odometry_;
  bool localized_;
  bool unconfirmed_ = false;  // the last scan was relocalized: the next one confirms it
  int lost_in_a_row_ = 0;
};

}  // namespace

const char* toString(Outcome outcome) {
  switch (outcome) {
    case Outcome::Tracked:
      return "tracked";
    case Outcome::Recovered:
      return "recovered";
    case Outcome::Relocalized:
      return "relocalized";
    case Outcome::Lost:
      return "lost";
  }
  return "?";
}

const char* placedIn(const ScanRecord& r) {
  if (r.outcome == Outcome::Lost) return "";
  if (r.in_live <= 0.05 * (r.in_prior + r.in_live)) return "prior";
  if (r.in_prior < 0.05 * (r.in_prior + r.in_live)) return "live";
  return "prior+live";
}

size_t TrackingResult::count(Outcome outcome) const {
  size_t n = 0;
  for (const ScanRecord& s : scans) n += s.outcome == outcome;
  return n;
}

TrackingResult track(const ndtom::NdtMap& map, apps::ScanSource& source,
                     const TrackingSettings& settings, const ReferenceLookup& reference,
                     apps::Progress& progress, size_t already_read) {
  const auto start = Clock::now();
  TrackingResult out;
  Tracker tracker(map, settings);
  progress.start("localizing", source.size() - std::min(source.size(), already_read));
  size_t points_done = 0;
  while (auto scan = source.next()) {
    const auto scan_start = Clock::now();
    ScanRecord record;
    record.index = already_read + out.scans.size();
    record.name = scan->name;
    record.time = scan->time;
    // --reference, where given, is the one asked for: it wins over the input's own poses.
    if (reference)
      record.reference = reference(record.index, record.time);
    else if (scan->pose_kind == PoseKind::Reference)
      record.reference = scan->frame_pose;
    tracker.localize(*scan, record, out);
    record.seconds = apps::secondsSince(scan_start);
    record.map_bytes = map.memoryBytes();
    record.rss_bytes = apps::currentRssBytes();
    points_done += record.points;
    out.scans.push_back(std::move(record));
    progress.update(out.scans.size(), points_done);
  }
  tracker.finish(out);
  progress.finish();
  out.extended_map = tracker.extendedMap();
  out.seconds = apps::secondsSince(start);
  return out;
}

}  // namespace ndtom::localizer
