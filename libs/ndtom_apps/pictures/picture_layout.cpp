#include "ndtom_apps/picture_layout.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

#include "ndtom_apps/round_step.h"

namespace ndtom::apps {
namespace {

const cv::Scalar kInk(40, 40, 40);
constexpr double kTitleScale = 0.65, kLegendScale = 0.48;
constexpr int kTitleLine = 24, kLegendLine = 20;  // px between baselines
const cv::Scalar kPaper(255, 255, 255);

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
  const double step = apps::roundStep(scale.z_max - scale.z_min, 6);
  for (double z = std::ceil(scale.z_min / step) * step; z <= scale.z_max + 1e-9; z += step) {
    const int y = top + int(std::lround((1.0 - scale.fraction(z)) * (bar_h - 1)));
    cv::line(canvas, {left + bar_w, y}, {left + bar_w + 5, y}, kInk, 1);
    drawText(canvas, apps::stepLabel(z, step), {left + bar_w + 8, y + 5}, 0.45, kInk);
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

}  // namespace ndtom::apps
