// The frame around a map view: a caption on top, a height colour bar on the right (the scale
// bar of views drawn to scale is ndtom_apps/top_canvas.h's).
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "ndtom_apps/height_colors.h"

namespace ndtom::apps {

inline constexpr int kLegendWidth = 120;  ///< px, right of the view

/// Width left for the view in a picture `picture_width` wide.
inline int viewWidth(int picture_width) {
  return picture_width - kLegendWidth;
}

/// The picture: `title` and `legend` above `view` (wrapped to its width), the colour bar of
/// `scale` beside it. The picture is view.cols + kLegendWidth wide.
cv::Mat composePicture(const cv::Mat& view, const std::string& title, const std::string& legend,
                       const HeightScale& scale);

/// Text drawn the same way everywhere (anti-aliased Hershey simplex); `scale` 1 is ~22 px.
void drawText(cv::Mat& image, const std::string& text, cv::Point origin, double scale,
              const cv::Scalar& color, int thickness = 1);

}  // namespace ndtom::apps
