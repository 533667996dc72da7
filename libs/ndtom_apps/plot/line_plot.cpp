#include "ndtom_apps/line_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace ndtom::apps {

namespace {

constexpr int kWidth = 1000, kHeight = 560;
constexpr int kLeft = 90, kRight = 230, kTop = 50, kBottom = 70;
const cv::Scalar kBlack{0, 0, 0}, kGridGrey{225, 225, 225};
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

struct Range {
  double lo, hi;
};

/// A round step giving about `count` intervals over `span`.
double niceStep(double span, int count) {
  const double raw = span / count;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (raw <= m * magnitude) return m * magnitude;
  return 10.0 * magnitude;
}

Range dataRange(const std::vector<PlotSeries>& series, bool use_x) {
  Range r{INFINITY, -INFINITY};
  for (const auto& s : series)
    for (double v : use_x ? s.x : s.y)
      if (std::isfinite(v)) r = {std::min(r.lo, v), std::max(r.hi, v)};
  if (!(r.lo <= r.hi)) r = {0, 1};
  if (r.hi - r.lo < 1e-12 * std::max(1.0, std::abs(r.hi))) r = {r.lo - 0.5, r.hi + 0.5};
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

/// Maps data to pixels inside the plot frame.
class Frame {
 public:
  Frame(Range x, Range y, bool log_y) : x_(x), y_(y), log_y_(log_y) {
    if (log_y_) y_ = {std::log10(y.lo), std::log10(y.hi)};
  }
  cv::Point toPixel(double x, double y) const {
    const double fy = ((log_y_ ? std::log10(y) : y) - y_.lo) / (y_.hi - y_.lo);
    const double fx = (x - x_.lo) / (x_.hi - x_.lo);
    return {kLeft + int(std::lround(fx * (kWidth - kLeft - kRight))),
            kHeight - kBottom - int(std::lround(fy * (kHeight - kTop - kBottom)))};
  }
  std::vector<double> yTicks() const {
    std::vector<double> ticks;
    if (log_y_) {
      for (double e = std::floor(y_.lo); e <= std::ceil(y_.hi); ++e)
        for (double m : {1.0, 2.0, 5.0})
          if (const double v = m * std::pow(10.0, e);
              std::log10(v) >= y_.lo - 1e-9 && std::log10(v) <= y_.hi + 1e-9)
            ticks.push_back(v);
      return ticks;
    }
    return linearTicks(y_);
  }
  std::vector<double> xTicks() const { return linearTicks(x_); }

 private:
  static std::vector<double> linearTicks(Range r) {
    const double step = niceStep(r.hi - r.lo, 6);
    std::vector<double> ticks;
    for (double v = std::ceil(r.lo / step - 1e-9) * step; v <= r.hi + 1e-9 * step; v += step)
      ticks.push_back(v);
    return ticks;
  }
  Range x_, y_;
  bool log_y_;
};

void drawAxes(cv::Mat& img, const Frame& frame, const PlotAxes& axes) {
  const int x0 = kLeft, x1 = kWidth - kRight, y0 = kTop, y1 = kHeight - kBottom;
  for (double t : frame.yTicks()) {
    const int y = frame.toPixel(0, t).y;
    cv::line(img, {x0, y}, {x1, y}, kGridGrey, 1);
    int baseline = 0;
    const std::string label = tickLabel(t);
    const cv::Size size = cv::getTextSize(label, kFont, 0.45, 1, &baseline);
    cv::putText(img, label, {x0 - 8 - size.width, y + size.height / 2}, kFont, 0.45, kBlack, 1,
                cv::LINE_AA);
  }
  for (double t : frame.xTicks()) {
    const int x = frame.toPixel(t, 1).x;
    cv::line(img, {x, y0}, {x, y1}, kGridGrey, 1);
    putCentred(img, tickLabel(t), {x, y1 + 16}, 0.45);
  }
  cv::rectangle(img, {x0, y0}, {x1, y1}, kBlack, 1);
  putCentred(img, axes.title, {(x0 + x1) / 2, kTop / 2}, 0.65);
  putCentred(img, axes.x_label, {(x0 + x1) / 2, kHeight - 22}, 0.55);
  putVertical(img, axes.y_label, {22, (y0 + y1) / 2});
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
    cv::drawMarker(img, p, s.color, index % 2 ? cv::MARKER_SQUARE : cv::MARKER_DIAMOND, 7, 1,
                   cv::LINE_AA);
  }
  flush();
  const int ly = kTop + 15 + 24 * index, lx = kWidth - kRight + 15;
  cv::line(img, {lx, ly}, {lx + 30, ly}, s.color, 2, cv::LINE_AA);
  cv::putText(img, s.label, {lx + 38, ly + 5}, kFont, 0.5, kBlack, 1, cv::LINE_AA);
}

}  // namespace

void writeLinePlot(const std::string& path, const PlotAxes& axes,
                   const std::vector<PlotSeries>& series) {
  Range y = dataRange(series, false);
  if (std::isfinite(axes.y_min)) y.lo = axes.y_min;
  if (std::isfinite(axes.y_max)) y.hi = axes.y_max;
  if (axes.log_y && !(y.lo > 0)) throw std::invalid_argument("log plot needs y > 0: " + path);
  const Frame frame(dataRange(series, true), y, axes.log_y);
  cv::Mat img(kHeight, kWidth, CV_8UC3, cv::Scalar::all(255));
  drawAxes(img, frame, axes);
  for (size_t i = 0; i < series.size(); ++i) drawSeries(img, frame, series[i], int(i));
  if (!cv::imwrite(path, img, {cv::IMWRITE_PNG_COMPRESSION, 9}))
    throw std::runtime_error("cannot write " + path);
}

}  // namespace ndtom::apps
