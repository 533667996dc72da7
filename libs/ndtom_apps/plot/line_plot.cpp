#include "ndtom_apps/line_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "ndtom_apps/round_step.h"

namespace ndtom::apps {

namespace {

const cv::Scalar kBlack{0, 0, 0}, kGridGrey{225, 225, 225};
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

struct Range {
  double lo, hi;
};

void widen(Range& r, double v) {
  if (std::isfinite(v)) r = {std::min(r.lo, v), std::max(r.hi, v)};
}

/// The data's range, `fixed_lo` and `fixed_hi` replacing its ends where finite.
Range dataRange(const std::vector<PlotSeries>& series, const std::vector<PlotLevel>& levels,
                bool use_x, double fixed_lo, double fixed_hi) {
  Range r{INFINITY, -INFINITY};
  for (const auto& s : series) {
    for (double v : use_x ? s.x : s.y) widen(r, v);
    if (!use_x)
      for (double v : s.bar_to) widen(r, v);
  }
  if (!use_x)
    for (const PlotLevel& l : levels) widen(r, l.y);
  if (!(r.lo <= r.hi)) r = {0, 1};
  if (r.hi - r.lo < 1e-12 * std::max(1.0, std::abs(r.hi))) r = {r.lo - 0.5, r.hi + 0.5};
  if (std::isfinite(fixed_lo)) r.lo = fixed_lo;
  if (std::isfinite(fixed_hi)) r.hi = fixed_hi;
  return r;
}

std::string tickLabel(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%g", std::abs(v) < 1e-12 ? 0.0 : v);
  return buffer;
}

void putCentred(cv::Mat& img, const std::string& text, cv::Point centre, double scale) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, kFont, scale, 1, &baseline);
  cv::putText(img, text, centre - cv::Point(size.width / 2, -size.height / 2), kFont, scale, kBlack,
              1, cv::LINE_AA);
}

void putVertical(cv::Mat& img, const std::string& text, cv::Point centre) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, kFont, 0.55, 1, &baseline);
  cv::Mat label(size.height + baseline + 4, size.width + 4, CV_8UC3, cv::Scalar::all(255));
  cv::putText(label, text, {2, size.height + 2}, kFont, 0.55, kBlack, 1, cv::LINE_AA);
  cv::rotate(label, label, cv::ROTATE_90_COUNTERCLOCKWISE);
  const cv::Rect where(centre.x - label.cols / 2, centre.y - label.rows / 2, label.cols,
                       label.rows);
  if ((where & cv::Rect(0, 0, img.cols, img.rows)) == where) label.copyTo(img(where));
}

/// One axis: data values to a fraction of the plot's side, linear or by log10.
class Scale {
 public:
  Scale(Range r, bool log) : log_(log), r_(log ? Range{std::log10(r.lo), std::log10(r.hi)} : r) {}
  double fraction(double v) const { return ((log_ ? std::log10(v) : v) - r_.lo) / (r_.hi - r_.lo); }
  /// Round values: 1, 2 and 5 per decade on a log axis, about 6 even steps otherwise.
  std::vector<double> ticks() const {
    std::vector<double> ticks;
    if (log_) {
      for (double e = std::floor(r_.lo); e <= std::ceil(r_.hi); ++e)
        for (double m : {1.0, 2.0, 5.0})
          if (const double v = m * std::pow(10.0, e);
              std::log10(v) >= r_.lo - 1e-9 && std::log10(v) <= r_.hi + 1e-9)
            ticks.push_back(v);
      return ticks;
    }
    const double step = roundStep(r_.hi - r_.lo, 6);
    for (double v = std::ceil(r_.lo / step - 1e-9) * step; v <= r_.hi + 1e-9 * step; v += step)
      ticks.push_back(v);
    return ticks;
  }

 private:
  bool log_;
  Range r_;  ///< log10 of the range on a log axis
};

/// Maps data to pixels inside the plot frame.
class Frame {
 public:
  Frame(const Scale& x, const Scale& y) : x_(x), y_(y) {}
  int px(double x) const {
    return kPlotLeft + int(std::lround(x_.fraction(x) * (kPlotRight - kPlotLeft)));
  }
  int py(double y) const {
    return kPlotBottom - int(std::lround(y_.fraction(y) * (kPlotBottom - kPlotTop)));
  }
  cv::Point toPixel(double x, double y) const { return {px(x), py(y)}; }
  const Scale& x() const { return x_; }
  const Scale& y() const { return y_; }

 private:
  Scale x_, y_;
};

void drawAxes(cv::Mat& img, const Frame& frame, const PlotAxes& axes) {
  const int x0 = kPlotLeft, x1 = kPlotRight, y0 = kPlotTop, y1 = kPlotBottom;
  for (double t : frame.y().ticks()) {
    const int y = frame.py(t);
    cv::line(img, {x0, y}, {x1, y}, kGridGrey, 1);
    int baseline = 0;
    const std::string label = tickLabel(t);
    const cv::Size size = cv::getTextSize(label, kFont, 0.45, 1, &baseline);
    cv::putText(img, label, {x0 - 8 - size.width, y + size.height / 2}, kFont, 0.45, kBlack, 1,
                cv::LINE_AA);
  }
  for (double t : axes.x_ticks.empty() ? frame.x().ticks() : axes.x_ticks) {
    const int x = frame.px(t);
    cv::line(img, {x, y0}, {x, y1}, kGridGrey, 1);
    putCentred(img, tickLabel(t), {x, y1 + 16}, 0.45);
  }
  cv::rectangle(img, {x0, y0}, {x1, y1}, kBlack, 1);
  putCentred(img, axes.title, {(x0 + x1) / 2, kPlotTop / 2}, 0.65);
  putCentred(img, axes.x_label, {(x0 + x1) / 2, kPlotHeight - 22}, 0.55);
  putVertical(img, axes.y_label, {22, (y0 + y1) / 2});
}

void drawLevel(cv::Mat& img, const Frame& frame, const PlotLevel& level) {
  const int y = frame.py(level.y);
  for (int x = kPlotLeft; x < kPlotRight; x += 20)  // dashed: 12 px on, 8 off
    cv::line(img, {x, y}, {std::min(x + 12, kPlotRight), y}, kBlack, 1);
  cv::putText(img, level.label, {kPlotLeft + 6, y - 6}, kFont, 0.45, kBlack, 1, cv::LINE_AA);
}

void drawMarker(cv::Mat& img, cv::Point p, const PlotSeries& s, int index) {
  switch (s.marker) {
    case PlotMarker::Outline:
      cv::drawMarker(img, p, s.color, index % 2 ? cv::MARKER_SQUARE : cv::MARKER_DIAMOND, 7, 1,
                     cv::LINE_AA);
      break;
    case PlotMarker::FilledCircle:
      cv::circle(img, p, 4, s.color, cv::FILLED, cv::LINE_AA);
      break;
    case PlotMarker::FilledSquare:
      cv::rectangle(img, p - cv::Point(4, 4), p + cv::Point(4, 4), s.color, cv::FILLED);
      break;
  }
}

void drawSeries(cv::Mat& img, const Frame& frame, const PlotSeries& s, int index) {
  std::vector<cv::Point> run;
  auto flush = [&] {
    if (run.size() > 1) cv::polylines(img, run, false, s.color, 2, cv::LINE_AA);
    run.clear();
  };
  for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
    if (!std::isfinite(s.y[i])) {
      flush();
      continue;
    }
    const cv::Point p = frame.toPixel(s.x[i], s.y[i]);
    run.push_back(p);
    if (i < s.bar_to.size() && std::isfinite(s.bar_to[i]))
      cv::line(img, p, frame.toPixel(s.x[i], s.bar_to[i]), s.color, 1, cv::LINE_AA);
    drawMarker(img, p, s, index);
  }
  flush();
  const int ly = kPlotTop + 15 + 24 * index, lx = kPlotRight + 15;
  cv::line(img, {lx, ly}, {lx + 30, ly}, s.color, 2, cv::LINE_AA);
  drawMarker(img, {lx + 15, ly}, s, index);
  cv::putText(img, s.label, {lx + 38, ly + 5}, kFont, 0.5, kBlack, 1, cv::LINE_AA);
}

}  // namespace

void writeLinePlot(const std::string& path, const PlotAxes& axes,
                   const std::vector<PlotSeries>& series) {
  const Range x = dataRange(series, axes.levels, true, axes.x_min, axes.x_max);
  const Range y = dataRange(series, axes.levels, false, axes.y_min, axes.y_max);
  if (axes.log_x && !(x.lo > 0)) throw std::invalid_argument("log plot needs x > 0: " + path);
  if (axes.log_y && !(y.lo > 0)) throw std::invalid_argument("log plot needs y > 0: " + path);
  const Frame frame(Scale(x, axes.log_x), Scale(y, axes.log_y));
  cv::Mat img(kPlotHeight, kPlotWidth, CV_8UC3, cv::Scalar::all(255));
  drawAxes(img, frame, axes);
  for (const PlotLevel& level : axes.levels) drawLevel(img, frame, level);
  for (size_t i = 0; i < series.size(); ++i) drawSeries(img, frame, series[i], int(i));
  if (!cv::imwrite(path, img, {cv::IMWRITE_PNG_COMPRESSION, 9}))
    throw std::runtime_error("cannot write " + path);
}

}  // namespace ndtom::apps
