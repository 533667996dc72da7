#include "time_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace ndtom::bench {

namespace {

constexpr int kWidth = 960, kHeight = 620;
constexpr int kLeft = 90, kRight = 250, kTop = 60, kBottom = 70;
const cv::Scalar kBlack(0, 0, 0), kGrey(215, 215, 215);

struct Axes {
  double x_lo, x_hi, y_lo, y_hi;  // log10 of the data range shown
  cv::Point at(double x, double y) const {
    const double u = (std::log10(x) - x_lo) / (x_hi - x_lo);
    const double v = (std::log10(y) - y_lo) / (y_hi - y_lo);
    return {kLeft + int(std::lround(u * (kWidth - kLeft - kRight))),
            kHeight - kBottom - int(std::lround(v * (kHeight - kTop - kBottom)))};
  }
};

cv::Scalar colourOf(size_t i) {
  static const cv::Scalar palette[] = {{180, 119, 31},  {14, 127, 255},  {44, 160, 44},
                                       {40, 39, 214},   {189, 103, 148}, {75, 86, 140},
                                       {194, 119, 227}, {127, 127, 127}};
  return palette[i % 8];
}

void text(cv::Mat& img, const std::string& s, cv::Point p, double scale = 0.5) {
  cv::putText(img, s, p, cv::FONT_HERSHEY_SIMPLEX, scale, kBlack, 1, cv::LINE_AA);
}

/// Filled circle for one thread, filled square for more: multi-threaded series stay
/// distinguishable where they lie on top of the single-thread ones.
void marker(cv::Mat& img, cv::Point p, const cv::Scalar& colour, bool threaded) {
  if (threaded)
    cv::rectangle(img, p - cv::Point(4, 4), p + cv::Point(4, 4), colour, cv::FILLED);
  else
    cv::circle(img, p, 4, colour, cv::FILLED, cv::LINE_AA);
}

void drawGrid(cv::Mat& img, const Axes& ax, const std::vector<double>& resolutions) {
  for (int d = int(std::floor(ax.y_lo)); d <= int(std::ceil(ax.y_hi)); ++d)
    for (double m : {1.0, 2.0, 5.0}) {
      const double y = m * std::pow(10.0, d);
      if (std::log10(y) < ax.y_lo - 1e-9 || std::log10(y) > ax.y_hi + 1e-9) continue;
      const cv::Point p = ax.at(std::pow(10.0, ax.x_lo), y);
      cv::line(img, p, {kWidth - kRight, p.y}, kGrey, 1);
      char label[32];
      std::snprintf(label, sizeof label, "%g", y);
      text(img, label, {kLeft - 60, p.y + 5});
    }
  for (double r : resolutions) {
    const cv::Point p = ax.at(r, std::pow(10.0, ax.y_lo));
    cv::line(img, p, {p.x, kTop}, kGrey, 1);
    char label[32];
    std::snprintf(label, sizeof label, "%g", r);
    text(img, label, {p.x - 12, p.y + 22});
  }
  cv::rectangle(img, {kLeft, kTop}, {kWidth - kRight, kHeight - kBottom}, kBlack, 1);
  text(img, "resolution (m)", {(kWidth - kRight + kLeft) / 2 - 60, kHeight - 20}, 0.6);
  text(img, "ms / scan", {10, kTop - 15}, 0.6);
}

}  // namespace

void writeTimePlot(const std::string& path, const std::vector<RunResult>& runs,
                   const std::string& dataset, const std::vector<double>& real_time_ms) {
  std::map<std::string, std::vector<const RunResult*>> series;  // label -> runs by resolution
  std::vector<std::string> order;
  std::vector<double> resolutions;
  double t_min = 1e300, t_max = 0;
  for (const RunResult& r : runs) {
    if (r.dataset != dataset || r.medianSeconds() <= 0) continue;
    if (!series.count(r.label)) order.push_back(r.label);
    series[r.label].push_back(&r);
    resolutions.push_back(r.resolution);
    t_min = std::min(t_min, r.medianSeconds() * 1e3);
    t_max = std::max(t_max, r.p95Seconds() * 1e3);
  }
  if (order.empty()) throw std::runtime_error("--plot: no timed run for " + dataset);
  for (double ms : real_time_ms) t_min = std::min(t_min, ms), t_max = std::max(t_max, ms);
  std::sort(resolutions.begin(), resolutions.end());
  resolutions.erase(std::unique(resolutions.begin(), resolutions.end()), resolutions.end());
  const double pad = 0.08;
  Axes ax{std::log10(resolutions.front()) - pad, std::log10(resolutions.back()) + pad,
          std::floor(std::log10(t_min)), std::ceil(std::log10(t_max))};
  if (ax.x_hi - ax.x_lo < 0.5) ax.x_lo -= 0.25, ax.x_hi += 0.25;
  if (ax.y_hi - ax.y_lo < 1) ax.y_hi += 1;

  cv::Mat img(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  drawGrid(img, ax, resolutions);
  text(img, "Insertion time per scan: " + dataset + " (median, bar to p95)", {kLeft, 30}, 0.65);
  for (double ms : real_time_ms) {  // dashed: 12 px on, 8 off
    const int y = ax.at(resolutions.front(), ms).y;
    for (int x = kLeft; x < kWidth - kRight; x += 20)
      cv::line(img, {x, y}, {std::min(x + 12, kWidth - kRight), y}, kBlack, 1);
    char label[48];
    std::snprintf(label, sizeof label, "scan period %g ms", ms);
    text(img, label, {kLeft + 6, y - 6}, 0.45);
  }
  for (size_t i = 0; i < order.size(); ++i) {
    auto& points = series[order[i]];
    std::sort(points.begin(), points.end(),
              [](const RunResult* a, const RunResult* b) { return a->resolution < b->resolution; });
    const cv::Scalar colour = colourOf(i);
    for (size_t k = 0; k < points.size(); ++k) {
      const cv::Point p = ax.at(points[k]->resolution, points[k]->medianSeconds() * 1e3);
      const cv::Point q = ax.at(points[k]->resolution, points[k]->p95Seconds() * 1e3);
      cv::line(img, p, q, colour, 1, cv::LINE_AA);
      marker(img, p, colour, points[k]->threads > 1);
      if (k > 0)
        cv::line(img, ax.at(points[k - 1]->resolution, points[k - 1]->medianSeconds() * 1e3), p,
                 colour, 2, cv::LINE_AA);
    }
    const int y = kTop + 20 + int(i) * 26;
    cv::line(img, {kWidth - kRight + 20, y - 5}, {kWidth - kRight + 50, y - 5}, colour, 2);
    marker(img, {kWidth - kRight + 35, y - 5}, colour, points.front()->threads > 1);
    text(img, order[i], {kWidth - kRight + 58, y});
  }
  bool written = false;
  try {
    written = cv::imwrite(path, img);
  } catch (const cv::Exception& e) {  // e.g. an unknown extension: keep the message one line
    throw std::runtime_error("--plot " + path + ": " + e.err);
  }
  if (!written) throw std::runtime_error("--plot " + path + ": cannot write");
}

}  // namespace ndtom::bench
