#include "time_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "ndtom_apps/line_plot.h"

namespace ndtom::bench {

namespace {

cv::Scalar colourOf(size_t i) {
  static const cv::Scalar palette[] = {{180, 119, 31},  {14, 127, 255},  {44, 160, 44},
                                       {40, 39, 214},   {189, 103, 148}, {75, 86, 140},
                                       {194, 119, 227}, {127, 127, 127}};
  return palette[i % 8];
}

}  // namespace

void writeTimePlot(const std::string& path, const std::vector<RunResult>& runs,
                   const std::string& dataset, const std::vector<double>& real_time_ms) {
  std::map<std::string, std::vector<const RunResult*>> by_label;
  std::vector<std::string> order;  // labels in the order the systems ran
  std::vector<double> resolutions;
  double t_min = 1e300, t_max = 0;
  for (const RunResult& r : runs) {
    if (r.dataset != dataset || r.medianSeconds() <= 0) continue;
    if (!by_label.count(r.label)) order.push_back(r.label);
    by_label[r.label].push_back(&r);
    resolutions.push_back(r.resolution);
    t_min = std::min(t_min, r.medianSeconds() * 1e3);
    t_max = std::max(t_max, r.p95Seconds() * 1e3);
  }
  if (order.empty()) throw std::runtime_error("--plot: no timed run for " + dataset);
  for (double ms : real_time_ms) t_min = std::min(t_min, ms), t_max = std::max(t_max, ms);
  std::sort(resolutions.begin(), resolutions.end());
  resolutions.erase(std::unique(resolutions.begin(), resolutions.end()), resolutions.end());

  apps::PlotAxes axes{"Insertion time per scan: " + dataset + " (median, bar to p95)",
                      "resolution (m)", "ms / scan"};
  axes.log_x = axes.log_y = true;
  axes.x_ticks = resolutions;
  // Whole decades of time, at least one; at least half a decade of resolution.
  axes.y_min = std::pow(10.0, std::floor(std::log10(t_min)));
  axes.y_max = std::pow(10.0, std::max(std::ceil(std::log10(t_max)), std::log10(axes.y_min) + 1));
  const double span = std::log10(resolutions.back() / resolutions.front());
  const double pad = span + 0.16 < 0.5 ? 0.33 : 0.08;  // decades beside the outer resolutions
  axes.x_min = resolutions.front() * std::pow(10.0, -pad);
  axes.x_max = resolutions.back() * std::pow(10.0, pad);
  for (double ms : real_time_ms) {
    char label[48];
    std::snprintf(label, sizeof label, "scan period %g ms", ms);
    axes.levels.push_back({ms, label});
  }

  std::vector<apps::PlotSeries> series;
  for (const std::string& label : order) {
    std::vector<const RunResult*>& points = by_label[label];
    std::sort(points.begin(), points.end(),
              [](const RunResult* a, const RunResult* b) { return a->resolution < b->resolution; });
    apps::PlotSeries s{label, {}, {}, colourOf(series.size())};
    // Squares for several threads: they stay visible where they lie on the one-thread line.
    s.marker = points.front()->threads > 1 ? apps::PlotMarker::FilledSquare
                                           : apps::PlotMarker::FilledCircle;
    for (const RunResult* r : points) {
      s.x.push_back(r->resolution);
      s.y.push_back(r->medianSeconds() * 1e3);
      s.bar_to.push_back(r->p95Seconds() * 1e3);
    }
    series.push_back(std::move(s));
  }
  try {
    apps::writeLinePlot(path, axes, series);
  } catch (const cv::Exception& e) {  // e.g. an unknown extension: keep the message one line
    throw std::runtime_error("--plot " + path + ": " + e.err);
  }
}

}  // namespace ndtom::bench
