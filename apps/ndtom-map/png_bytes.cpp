#include "png_bytes.h"

#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <vector>

namespace ndtom::mapper {

std::string pngBytes(const cv::Mat& image) {
  std::vector<uint8_t> png;
  // Full compression: a few tenths of a second for pictures a third smaller.
  if (!cv::imencode(".png", image, png, {cv::IMWRITE_PNG_COMPRESSION, 9}))
    throw std::runtime_error("cannot encode a PNG picture");
  return std::string(png.begin(), png.end());
}

}  // namespace ndtom::mapper
