#include "ndtom_io/tum_rgbd.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <sstream>

#include "ndtom_internal/checked_size.h"
#include "ndtom_internal/input_file.h"
#include "ndtom_io/pose_file.h"

namespace ndtom::io {
namespace fs = std::filesystem;
namespace {

constexpr double kMaxTimeDifference = 0.02;  // s, as TUM's associate.py
constexpr uint64_t kMaxTableBytes = uint64_t(1) << 28;
constexpr uint64_t kMaxDepthImageBytes = uint64_t(1) << 28;

std::vector<std::vector<std::string>> readTable(const fs::path& path) {
  std::istringstream in;
  try {
    in.str(readInputFile(path.string(), kMaxTableBytes, "TUM sequence:"));
  } catch (const InputFileError& e) {
    throw TumError(e.what());
  }
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::vector<std::string> row;
    for (std::string t; s >> t;) row.push_back(t);
    if (!row.empty()) rows.push_back(row);
  }
  return rows;
}

double number(const std::string& token, const fs::path& file) {
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end == token.c_str() || *end != '\0' || !std::isfinite(v))
    throw TumError("TUM sequence: bad number '" + token + "' in " + file.string());
  return v;
}

// Depth files with their time stamps, matched to the nearest ground-truth pose.
TumSequence matchGroundTruth(const fs::path& folder,
                             const std::vector<std::pair<double, std::string>>& depth_files) {
  const auto truth = readPoseFile((folder / "groundtruth.txt").string(), PoseFormat::Tum);
  std::map<double, Eigen::Isometry3d> by_time;
  for (const auto& p : truth) by_time.emplace(p.time, p.pose);
  TumSequence seq;
  for (const auto& [time, file] : depth_files) {
    auto best = by_time.end();
    auto it = by_time.lower_bound(time);
    for (auto candidate : {it, it == by_time.begin() ? by_time.end() : std::prev(it)}) {
      if (candidate == by_time.end()) continue;
      if (best == by_time.end() || std::abs(candidate->first - time) < std::abs(best->first - time))
        best = candidate;
    }
    if (best == by_time.end() || std::abs(best->first - time) > kMaxTimeDifference) {
      ++seq.frames_without_pose;
      continue;
    }
    seq.frames.push_back({time, (folder / file).string(), best->second});
  }
  return seq;
}

// A PNG's size from its IHDR chunk (the first one, right after the signature), so that a
// header claiming 100000 x 100000 pixels is refused before OpenCV allocates them.
struct PngHeader {
  uint64_t width = 0, height = 0;
  int bit_depth = 0, color_type = 0;
};

std::optional<PngHeader> pngHeader(const std::string& bytes) {
  static const char kSignature[] = "\x89PNG\r\n\x1a\n";
  if (bytes.size() < 29 || bytes.compare(0, 8, kSignature, 8) != 0 ||
      bytes.compare(12, 4, "IHDR") != 0)
    return std::nullopt;
  auto u32 = [&](size_t at) {
    uint64_t v = 0;
    for (size_t i = 0; i < 4; ++i) v = v << 8 | uint8_t(bytes[at + i]);
    return v;
  };
  return PngHeader{u32(16), u32(20), uint8_t(bytes[24]), uint8_t(bytes[25])};
}

}  // namespace

void DepthCamera::validate() const {
  auto check = [](double v, const char* name, bool ok) {
    if (!ok || !std::isfinite(v))
      throw std::invalid_argument(
          std::string(name) + " = " + std::to_string(v) + ": must be " +
          (std::string(name) == "cx" || std::string(name) == "cy" ? "finite" : "finite and > 0"));
  };
  check(fx, "fx", fx > 0);
  check(fy, "fy", fy > 0);
  check(cx, "cx", true);
  check(cy, "cy", true);
  check(depth_scale, "depth_scale", depth_scale > 0);
}

TumSequence readTumSequence(const std::string& folder_name) {
  const fs::path folder(folder_name);
  if (!fs::is_directory(folder))
    throw TumError("TUM sequence: " + folder_name + " is not a folder");
  const fs::path associations = folder / "associations.txt";
  if (fs::exists(associations)) {
    const auto rows = readTable(associations);
    if (rows.empty()) throw TumError("TUM sequence: " + associations.string() + " is empty");
    if (rows[0].size() == 9) {  // rgb depth tx ty tz qx qy qz qw
      TumSequence seq;
      for (const auto& r : rows) {
        if (r.size() != 9)
          throw TumError("TUM sequence: inconsistent rows in " + associations.string());
        double v[7];
        for (int i = 0; i < 7; ++i) v[i] = number(r[2 + i], associations);
        TumFrame f;
        const std::string stem = fs::path(r[1]).stem().string();
        f.time = std::strtod(stem.c_str(), nullptr);
        f.depth_path = (folder / r[1]).string();
        try {
          f.camera_to_world = poseFromTranslationQuaternion(v, v[3], v[4], v[5], v[6]);
        } catch (const std::invalid_argument& e) {
          throw TumError("TUM sequence: " + associations.string() + ": " + e.what());
        }
        seq.frames.push_back(f);
      }
      return seq;
    }
    if (rows[0].size() == 4) {  // associate.py: t rgb t depth
      std::vector<std::pair<double, std::string>> depth_files;
      for (const auto& r : rows) {
        if (r.size() != 4)
          throw TumError("TUM sequence: inconsistent rows in " + associations.string());
        depth_files.emplace_back(number(r[2], associations), r[3]);
      }
      return matchGroundTruth(folder, depth_files);
    }
    throw TumError("TUM sequence: " + associations.string() +
                   ": expected 9 columns (files + pose) or 4 (associate.py output)");
  }
  if (fs::exists(folder / "depth.txt")) {
    std::vector<std::pair<double, std::string>> depth_files;
    for (const auto& r : readTable(folder / "depth.txt")) {
      if (r.size() != 2) throw TumError("TUM sequence: depth.txt must have 2 columns");
      depth_files.emplace_back(number(r[0], folder / "depth.txt"), r[1]);
    }
    return matchGroundTruth(folder, depth_files);
  }
  throw TumError("TUM sequence: " + folder_name + " has neither associations.txt nor depth.txt");
}

std::vector<Eigen::Vector3d> readDepthImagePoints(const std::string& png_path,
                                                  const DepthCamera& camera, int decimation,
                                                  uint64_t max_points) {
  camera.validate();
  if (decimation < 1) throw std::invalid_argument("decimation must be >= 1");
  std::string bytes;
  try {
    bytes = readInputFile(png_path, kMaxDepthImageBytes, "depth image");
  } catch (const InputFileError& e) {
    throw TumError(e.what());
  }
  const auto header = pngHeader(bytes);
  if (!header) throw TumError("depth image " + png_path + ": not a PNG file");
  if (header->bit_depth != 16 || header->color_type != 0)
    throw TumError("depth image " + png_path + ": not 16-bit single channel");
  const auto pixels = checkedMul(header->width, header->height);
  if (!pixels || *pixels > kMaxDepthImagePixels || header->width == 0 || header->height == 0)
    throw TumError("depth image " + png_path + ": " + std::to_string(header->width) + " x " +
                   std::to_string(header->height) + " pixels (at most " +
                   std::to_string(kMaxDepthImagePixels) + " are read)");
  const uint64_t step = uint64_t(decimation);
  const uint64_t most_points =
      ((header->width + step - 1) / step) * ((header->height + step - 1) / step);
  if (most_points > max_points)
    throw TumError("depth image " + png_path + ": up to " + std::to_string(most_points) +
                   " points at decimation " + std::to_string(decimation) + ", more than the " +
                   std::to_string(max_points) + " a scan may have here");
  const cv::Mat depth =
      cv::imdecode(cv::Mat(1, int(bytes.size()), CV_8UC1, bytes.data()), cv::IMREAD_UNCHANGED);
  if (depth.empty()) throw TumError("depth image " + png_path + ": cannot decode it");
  if (depth.type() != CV_16UC1 || uint64_t(depth.cols) != header->width ||
      uint64_t(depth.rows) != header->height)
    throw TumError("depth image " + png_path + ": not 16-bit single channel");
  std::vector<Eigen::Vector3d> points;
  size_t readings = 0;  // reserve exactly: most pixels of a depth image may be empty
  for (int v = 0; v < depth.rows; v += decimation) {
    const auto* row = depth.ptr<uint16_t>(v);
    for (int u = 0; u < depth.cols; u += decimation) readings += row[u] != 0;
  }
  points.reserve(readings);
  for (int v = 0; v < depth.rows; v += decimation) {
    const auto* row = depth.ptr<uint16_t>(v);
    for (int u = 0; u < depth.cols; u += decimation) {
      if (row[u] == 0) continue;
      const double z = row[u] / camera.depth_scale;
      points.emplace_back((u - camera.cx) * z / camera.fx, (v - camera.cy) * z / camera.fy, z);
    }
  }
  return points;
}

}  // namespace ndtom::io
