#include "ndtom_io/tum_rgbd.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "ndtom_io/pose_file.h"

namespace ndtom::io {
namespace fs = std::filesystem;
namespace {

constexpr double kMaxTimeDifference = 0.02;  // s, as TUM's associate.py

std::vector<std::vector<std::string>> readTable(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw TumError("TUM sequence: cannot open " + path.string());
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
                                                  const DepthCamera& camera, int decimation) {
  camera.validate();
  if (decimation < 1) throw std::invalid_argument("decimation must be >= 1");
  const cv::Mat depth = cv::imread(png_path, cv::IMREAD_UNCHANGED);
  if (depth.empty()) throw TumError("depth image " + png_path + ": cannot read it");
  if (depth.type() != CV_16UC1)
    throw TumError("depth image " + png_path + ": not 16-bit single channel");
  std::vector<Eigen::Vector3d> points;
  points.reserve(size_t(depth.rows / decimation + 1) * size_t(depth.cols / decimation + 1));
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
