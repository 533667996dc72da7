// Line plots drawn with OpenCV (no plotting dependency): axes with round ticks, linear or
// logarithmic, one coloured line with markers per series (optionally a bar per point, e.g.
// up to a percentile), a legend to the right.
#pragma once

#include <cstdint>
#include <limits>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace ndtom::apps {

enum class PlotMarker : uint8_t {
  Outline,       ///< diamond or square by the series' index
  FilledCircle,  ///< with FilledSquare: two kinds of series that may lie on top of each other
  FilledSquare,
};

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;  ///< same length; NaN y values leave a gap
  cv::Scalar color;          ///< BGR
  /// Empty, or as long as y: a thin vertical bar from each y to this value.
  std::vector<double> bar_to = {};
  PlotMarker marker = PlotMarker::Outline;
};

/// A dashed horizontal line across the plot, labelled above its left end.
struct PlotLevel {
  double y;
  std::string label;
};

struct PlotAxes {
  std::string title, x_label, y_label;
  /// Fixed ranges; NaN = fit the data (y: the bars too).
  double y_min = std::numeric_limits<double>::quiet_NaN();
  double y_max = std::numeric_limits<double>::quiet_NaN();
  bool log_y = false;  ///< logarithmic y axis (all y must be > 0)
  double x_min = std::numeric_limits<double>::quiet_NaN();
  double x_max = std::numeric_limits<double>::quiet_NaN();
  bool log_x = false;                ///< logarithmic x axis (all x must be > 0)
  std::vector<double> x_ticks = {};  ///< empty: round ticks
  std::vector<PlotLevel> levels = {};
};

/// Where the plot area lies in the picture (px); points map linearly (or by log10) onto it,
/// x_min at its left edge, y_min at its bottom edge.
inline constexpr int kPlotWidth = 1000, kPlotHeight = 560;
inline constexpr int kPlotLeft = 90, kPlotRight = kPlotWidth - 230;
inline constexpr int kPlotTop = 50, kPlotBottom = kPlotHeight - 70;

/// Draws the plot and writes a PNG; throws std::runtime_error if the file cannot be written,
/// std::invalid_argument if a log axis gets values <= 0.
void writeLinePlot(const std::string& path, const PlotAxes& axes,
                   const std::vector<PlotSeries>& series);

}  // namespace ndtom::apps
