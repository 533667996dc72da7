#include "ndtom_apps/png_bytes.h"

#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <vector>

namespace ndtom::apps {

std::string pngBytes(const cv::Mat& image) {
  std::vector<uint8_t> png;
  // zlib level 3: the lidar map's two pictures took 1.05 s at level 9 and take 0.15 s,
  // for files 2 % larger (doc/benchmarks.md, "ndtom-map end to end").
  if (!cv::imencode(".png", image, png, {cv::IMWRITE_PNG_COMPRESSION, 3}))
    throw std::runtime_error("cannot encode a PNG picture");
  return std::string(png.begin(), png.end());
}

}  // namespace ndtom::apps
