// The line plot's axes, bars and levels: where marks land in the written PNG, against
// positions worked out by hand from the plot area's corners.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "ndtom_apps/line_plot.h"

namespace fs = std::filesystem;
using ndtom::apps::kPlotBottom;
using ndtom::apps::kPlotLeft;
using ndtom::apps::kPlotRight;
using ndtom::apps::kPlotTop;
using ndtom::apps::PlotAxes;
using ndtom::apps::PlotMarker;
using ndtom::apps::PlotSeries;

namespace {

// Colours used by nothing else in a plot (the axes are black and grey).
const cv::Scalar kColours[] = {{0, 0, 255}, {0, 200, 0}, {255, 0, 0}};

struct Plot {
  cv::Mat image;
  explicit Plot(const PlotAxes& axes, const std::vector<PlotSeries>& series) {
    const fs::path path =
        fs::temp_directory_path() / ("line_plot_" + std::to_string(getpid()) + ".png");
    ndtom::apps::writeLinePlot(path.string(), axes, series);
    image = cv::imread(path.string(), cv::IMREAD_COLOR);
    fs::remove(path);
  }
  bool is(int x, int y, const cv::Scalar& c) const {
    const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
    return p[0] == c[0] && p[1] == c[1] && p[2] == c[2];
  }
  // The centre of the pixels of exactly colour `c` inside the plot area (not the legend).
  cv::Point2d centreOf(const cv::Scalar& c) const {
    double sx = 0, sy = 0, n = 0;
    for (int y = kPlotTop; y <= kPlotBottom; ++y)
      for (int x = kPlotLeft; x <= kPlotRight; ++x)
        if (is(x, y, c)) sx += x, sy += y, ++n;
    return n > 0 ? cv::Point2d(sx / n, sy / n) : cv::Point2d(NAN, NAN);
  }
};

// One square marker per series, so that each colour marks one point.
std::vector<PlotSeries> points(const std::vector<cv::Point2d>& xy) {
  std::vector<PlotSeries> series;
  for (size_t i = 0; i < xy.size(); ++i)
    series.push_back(
        {"p" + std::to_string(i), {xy[i].x}, {xy[i].y}, kColours[i], {}, PlotMarker::FilledSquare});
  return series;
}

double xAt(double fraction) {
  return kPlotLeft + fraction * (kPlotRight - kPlotLeft);
}
double yAt(double fraction) {
  return kPlotBottom - fraction * (kPlotBottom - kPlotTop);
}

}  // namespace

TEST(LinePlot, LogXAxisPlacesDecadesEvenly) {
  PlotAxes axes{"log x", "x", "y"};
  axes.log_x = true;
  axes.x_min = 0.1, axes.x_max = 1e4;  // five decades
  axes.y_min = 0, axes.y_max = 2;
  const Plot plot(axes, points({{1, 1}, {10, 1}, {1000, 1}}));
  // 1, 10 and 1000 lie one, two and four decades of five from the left; all at half height.
  const double fractions[] = {0.2, 0.4, 0.8};
  for (int i = 0; i < 3; ++i) {
    const cv::Point2d c = plot.centreOf(kColours[i]);
    EXPECT_NEAR(c.x, xAt(fractions[i]), 1.0) << i;
    EXPECT_NEAR(c.y, yAt(0.5), 1.0) << i;
  }
}

TEST(LinePlot, LogYAxisPlacesDecadesEvenly) {
  PlotAxes axes{"log y", "x", "y"};
  axes.log_y = true;
  axes.y_min = 1, axes.y_max = 1000;  // three decades
  axes.x_min = 0, axes.x_max = 4;
  const Plot plot(axes, points({{1, 10}, {3, 100}}));
  EXPECT_NEAR(plot.centreOf(kColours[0]).y, yAt(1.0 / 3), 1.0);
  EXPECT_NEAR(plot.centreOf(kColours[1]).y, yAt(2.0 / 3), 1.0);
  EXPECT_NEAR(plot.centreOf(kColours[0]).x, xAt(0.25), 1.0);
}

TEST(LinePlot, LogAxesRefuseValuesAtOrBelowZero) {
  PlotAxes axes{"log x", "x", "y"};
  axes.log_x = true;
  EXPECT_THROW(ndtom::apps::writeLinePlot("/nonexistent/never.png", axes, points({{0, 1}})),
               std::invalid_argument);
}

TEST(LinePlot, BarRunsFromThePointToItsEndAndNoFurther) {
  PlotAxes axes{"bars", "x", "y"};
  axes.x_min = 0, axes.x_max = 10;
  axes.y_min = 0, axes.y_max = 10;
  std::vector<PlotSeries> series = points({{5, 2}});
  series[0].bar_to = {8};
  const Plot plot(axes, series);
  const int x = int(std::lround(xAt(0.5)));
  // The topmost pixel near the bar's column that has the series' colour in it (the bar is
  // anti-aliased: mostly red, little blue or green).
  int top = -1;
  for (int y = kPlotTop + 1; y < kPlotBottom && top < 0; ++y)
    for (int dx = -1; dx <= 1; ++dx) {
      const cv::Vec3b p = plot.image.at<cv::Vec3b>(y, x + dx);
      if (p[2] > 200 && p[1] < 100 && p[0] < 100) top = y;
    }
  EXPECT_NEAR(top, yAt(0.8), 1.0) << "the bar ends at 8 of 10";
  // And it is there all the way down to the marker at 2.
  for (int y = int(std::lround(yAt(0.8))) + 1; y < int(std::lround(yAt(0.2))); ++y) {
    const cv::Vec3b p = plot.image.at<cv::Vec3b>(y, x);
    EXPECT_GT(int(p[2]) - int(p[1]), 100) << "gap in the bar at y " << y;
  }
  EXPECT_NEAR(plot.centreOf(kColours[0]).y, yAt(0.2), 1.0);
}

TEST(LinePlot, LevelIsADashedLineAtItsValue) {
  PlotAxes axes{"level", "x", "y"};
  axes.x_min = 0, axes.x_max = 10;
  axes.y_min = 0, axes.y_max = 10;
  axes.levels = {{3, "three"}};
  const Plot plot(axes, points({{5, 8}}));
  const int y = int(std::lround(yAt(0.3)));
  const cv::Scalar black(0, 0, 0), white(255, 255, 255);
  // Dashes of 13 px every 20 px from the left edge of the plot area.
  for (int dash = 0; dash < 5; ++dash) {
    EXPECT_TRUE(plot.is(kPlotLeft + 20 * dash + 6, y, black)) << dash;
    EXPECT_TRUE(plot.is(kPlotLeft + 20 * dash + 16, y, white)) << dash;
  }
  EXPECT_TRUE(plot.is(kPlotLeft + 6, y + 3, white)) << "one pixel thick";
}
