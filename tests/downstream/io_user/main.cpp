// Reads the installed TUM demo sequence (argv[1]): its ten frames, and the first depth image
// as points, which must be as many as OpenCV finds non-zero pixels in the same PNG.
#include <ndtom_io/tum_rgbd.h>

#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: io_user TUM_FOLDER\n");
    return 2;
  }
  const ndtom::io::TumSequence sequence = ndtom::io::readTumSequence(argv[1]);
  if (sequence.frames.size() != 10) {
    std::printf("io_user: %zu frames, expected 10\n", sequence.frames.size());
    return 1;
  }
  const std::string& png = sequence.frames.front().depth_path;
  const auto points = ndtom::io::readDepthImagePoints(png, ndtom::io::DepthCamera{});
  const int non_zero = cv::countNonZero(cv::imread(png, cv::IMREAD_ANYDEPTH));
  std::printf("io_user: %zu frames, %zu points, %d non-zero pixels in %s\n", sequence.frames.size(),
              points.size(), non_zero, png.c_str());
  return non_zero > 0 && points.size() == size_t(non_zero) ? 0 : 1;
}
