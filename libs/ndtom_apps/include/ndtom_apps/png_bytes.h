// Pictures as PNG file contents, for OutputFiles::writeBytes.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace ndtom::apps {

/// Throws std::runtime_error if OpenCV cannot encode `image`.
std::string pngBytes(const cv::Mat& image);

}  // namespace ndtom::apps
