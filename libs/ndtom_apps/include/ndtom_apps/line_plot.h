// Line plots drawn with OpenCV (no plotting dependency): axes with round ticks, one
// coloured line with markers per series, a legend to the right.
#pragma once

#include <limits>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace ndtom::apps {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;  ///< same length; NaN y values leave a gap
  cv::Scalar color;          ///< BGR
};

struct PlotAxes {
  std::string title, x_label, y_label;
  /// Fixed y range; NaN = fit the data.
  double y_min = std::numeric_limits<double>::quiet_NaN();
  double y_max = std::numeric_limits<double>::quiet_NaN();
  bool log_y = false;  ///< logarithmic y axis (all y must be > 0)
};

/// Draws the plot and writes a PNG; throws std::runtime_error if the file cannot be written.
void writeLinePlot(const std::string& path, const PlotAxes& axes,
                   const std::vector<PlotSeries>& series);

}  // namespace ndtom::apps
