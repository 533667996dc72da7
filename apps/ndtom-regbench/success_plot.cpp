#include "success_plot.h"

#include <cmath>
#include <cstdio>

#include "ndtom_apps/line_plot.h"

namespace ndtom::regbench {

namespace {

// BGR, one per system in the order the systems ran.
const cv::Scalar kSeriesColors[] = {{40, 150, 40}, {200, 90, 30},  {40, 40, 210},
                                    {0, 140, 230}, {160, 60, 150}, {60, 60, 60}};

constexpr double kDodge = 0.7;  // percentage points between neighbouring lines

std::string xLabel(const std::vector<ErrorLevel>& levels) {
  std::string turns;
  for (const ErrorLevel& l : levels) {
    char text[32];
    std::snprintf(text, sizeof text, "%s%g", turns.empty() ? "" : ", ", l.degrees);
    turns += text;
  }
  return "initial error: translation (m), with a rotation of " + turns + " deg";
}

}  // namespace

void writeSuccessPlot(const std::string& path, const std::string& dataset,
                      const std::vector<LevelSummary>& summaries,
                      const std::vector<ErrorLevel>& levels) {
  std::vector<apps::PlotSeries> series;
  for (const LevelSummary& s : summaries) {
    if (s.threads != 1) continue;
    if (series.empty() || series.back().label != s.label) {
      const cv::Scalar color = kSeriesColors[series.size() % std::size(kSeriesColors)];
      series.push_back({s.label, {}, {}, color});
    }
    series.back().x.push_back(s.level.meters);
    series.back().y.push_back(100 * s.successRate());
  }
  // Equal rates (all at 100 %, say) would hide each other: each line is drawn shifted by a
  // fraction of a percent, the set centred on the true value (said under the x axis).
  for (size_t i = 0; i < series.size(); ++i)
    for (double& y : series[i].y) y += kDodge * (double(i) - 0.5 * double(series.size() - 1));
  char y_label[64];
  std::snprintf(y_label, sizeof y_label, "success (%%; ties drawn %g apart)", kDodge);
  apps::PlotAxes axes{"Registration success (final pose within 0.10 m and 1 deg): " + dataset,
                      xLabel(levels), y_label};
  axes.y_min = -2;  // lines at 0 and 100 % stay clear of the frame
  axes.y_max = 102;
  try {
    apps::writeLinePlot(path, axes, series);
  } catch (const cv::Exception& e) {  // e.g. an unknown extension: keep the message one line
    throw std::runtime_error("--plot " + path + ": " + e.err);
  }
}

}  // namespace ndtom::regbench
