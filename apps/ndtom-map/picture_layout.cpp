#include "picture_layout.h"

#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

namespace ndtom::mapper {
namespace {

const cv::Scalar kInk(40, 40, 40);
constexpr double kTitleScale = 0.65, kLegendScale = 0.48;
constexpr int kTitleLine = 24, kLegendLine = 20;  // px between baselines
const cv::Scalar kPaper(255, 255, 255);

std::string metres(double value, double step) {
  char text[32];
  const int decimals = step >= 1 ? 0 : (step >= 0.1 ? 1 : 2);
  if (std::abs(value) < 1e-3 * step) value = 0;  // no "-0"
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

// A step of 1, 2 or 5 times a power of ten that splits `span` into about `parts`.
double roundStep(double span, int parts) {
  const double raw = span / parts;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0})
    if (m * power >= raw) return m * power;
  return 10 * power;
}

void drawColorBar(cv::Mat& canvas, const cv::Rect& area, const HeightScale& scale) {
  const int bar_w = 22, top = area.y + 34;
  const int bar_h = std::min(area.height - 60, 420);
  if (bar_h < 40) return;
  const int left = area.x + 16;
  drawText(canvas, "height", {area.x + 10, area.y + 14}, 0.5, kInk);
  drawText(canvas, "z [m]", {area.x + 10, area.y + 28}, 0.45, kInk);
  for (int row = 0; row < bar_h; ++row) {
    const double z = scale.z_max - (scale.z_max - scale.z_min) * row / double(bar_h - 1);
    cv::line(canvas, {left, top + row}, {left + bar_w - 1, top + row}, scale.bgr(z));
  }
  cv::rectangle(canvas, {left, top, bar_w, bar_h}, kInk, 1);
  const double step = roundStep(scale.z_max - scale.z_min, 6);
  for (double z = std::ceil(scale.z_min / step) * step; z <= scale.z_max + 1e-9; z += step) {
    const int y = top + int(std::lround((1.0 - scale.fraction(z)) * (bar_h - 1)));
    cv::line(canvas, {left + bar_w, y}, {left + bar_w + 5, y}, kInk, 1);
    drawText(canvas, metres(z, step), {left + bar_w + 8, y + 5}, 0.45, kInk);
  }
}

// Words of `text` in lines no wider than `width` pixels.
std::vector<std::string> wrapText(const std::string& text, int width, double scale, int thickness) {
  std::vector<std::string> lines;
  std::istringstream words(text);
  std::string line;
  for (std::string word; words >> word;) {
    const std::string longer = line.empty() ? word : line + " " + word;
    int baseline = 0;
    const int w =
        cv::getTextSize(longer, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &baseline).width;
    if (w > width && !line.empty()) {
      lines.push_back(line);
      line = word;
    } else {
      line = longer;
    }
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

}  // namespace

void drawText(cv::Mat& image, const std::string& text, cv::Point origin, double scale,
              const cv::Scalar& color, int thickness) {
  cv::putText(image, text, origin, cv::FONT_HERSHEY_SIMPLEX, scale, color, thickness, cv::LINE_AA);
}

cv::Mat composePicture(const cv::Mat& view, const std::string& title, const std::string& legend,
                       const HeightScale& scale) {
  const int width = view.cols + kLegendWidth;
  const auto title_lines = wrapText(title, width - 24, kTitleScale, 2);
  const auto legend_lines = wrapText(legend, width - 24, kLegendScale, 1);
  const int caption =
      14 + kTitleLine * int(title_lines.size()) + kLegendLine * int(legend_lines.size());
  cv::Mat canvas(view.rows + caption, width, CV_8UC3, kPaper);
  view.copyTo(canvas(cv::Rect(0, caption, view.cols, view.rows)));
  int y = 4;
  for (const auto& line : title_lines)
    drawText(canvas, line, {12, y += kTitleLine}, kTitleScale, kInk, 2);
  y += 2;
  for (const auto& line : legend_lines)
    drawText(canvas, line, {12, y += kLegendLine}, kLegendScale, kInk);
  drawColorBar(canvas, {view.cols, caption, kLegendWidth, view.rows}, scale);
  return canvas;
}

void drawScaleBar(cv::Mat& view, double pixels_per_metre) {
  if (!(pixels_per_metre > 0)) return;
  const double length = roundStep(0.2 * view.cols / pixels_per_metre, 1);
  const int bar = int(std::lround(length * pixels_per_metre));
  const cv::Point start(20, view.rows - 20);
  if (bar < 10 || bar > view.cols - 40) return;
  cv::Mat box = view(cv::Rect(10, view.rows - 50, bar + 20, 42));
  const cv::Mat paper(box.size(), box.type(), kPaper);
  cv::addWeighted(box, 0.35, paper, 0.65, 0.0, box);  // readable on any map
  cv::line(view, start, start + cv::Point(bar, 0), kInk, 3);
  cv::line(view, start + cv::Point(0, -6), start + cv::Point(0, 6), kInk, 2);
  cv::line(view, start + cv::Point(bar, -6), start + cv::Point(bar, 6), kInk, 2);
  drawText(view, metres(length, length) + " m", start + cv::Point(0, -12), 0.5, kInk);
}

}  // namespace ndtom::mapper
