#include "ndtom_io/pose_file.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "ndtom_internal/atomic_file.h"
#include "ndtom_internal/input_file.h"

namespace ndtom::io {
namespace {

constexpr uint64_t kMaxPoseFileBytes = uint64_t(1) << 28;

const char* formatName(PoseFormat format) {
  return format == PoseFormat::Kitti ? "KITTI (12 numbers)" : "TUM (8 numbers)";
}

}  // namespace

std::string kittiPoseText(const std::vector<Eigen::Isometry3d>& poses) {
  std::string text;
  char number[32];
  for (const Eigen::Isometry3d& pose : poses) {
    const Eigen::Matrix<double, 3, 4> m = pose.matrix().topRows<3>();
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 4; ++col) {
        std::snprintf(number, sizeof number, "%.17g", m(row, col));
        text += number;
        text += row == 2 && col == 3 ? '\n' : ' ';
      }
  }
  return text;
}

void writeKittiPoseFile(const std::string& path, const std::vector<Eigen::Isometry3d>& poses) {
  const std::string text = kittiPoseText(poses);
  try {
    writeFileAtomically(path, text.data(), text.size());
  } catch (const std::runtime_error& e) {
    throw PoseFileError(std::string("pose file: ") + e.what());
  }
}

Eigen::Isometry3d poseFromTranslationQuaternion(const double t[3], double qx, double qy, double qz,
                                                double qw) {
  const Eigen::Quaterniond q(qw, qx, qy, qz);
  if (!(std::isfinite(q.norm()) && q.norm() > 1e-6))
    throw std::invalid_argument("zero or non-finite quaternion");
  if (!(std::isfinite(t[0]) && std::isfinite(t[1]) && std::isfinite(t[2])))
    throw std::invalid_argument("non-finite translation");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q.normalized().toRotationMatrix();
  pose.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
  return pose;
}

std::vector<StampedPose> readPoseFile(const std::string& path, PoseFormat format,
                                      PoseFormat* used) {
  std::istringstream in;
  try {
    in.str(readInputFile(path, kMaxPoseFileBytes, "pose file"));
  } catch (const InputFileError& e) {
    throw PoseFileError(e.what());
  }
  const bool guessed = format == PoseFormat::Auto;
  std::vector<StampedPose> poses;
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    const auto where = [&] { return "pose file " + path + ", line " + std::to_string(line_no); };
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream s(line);
    std::vector<double> v;
    std::string token;
    while (s >> token) {
      char* end = nullptr;
      const double x = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0' || !std::isfinite(x))
        throw PoseFileError(where() + ": bad number '" + token + "'");
      v.push_back(x);
    }
    // The first data line decides the format of the whole file: a file mixing the two would
    // otherwise give KITTI lines (numbered) and TUM lines (timed) one sequence.
    if (format == PoseFormat::Auto) {
      if (v.size() == 12)
        format = PoseFormat::Kitti;
      else if (v.size() == 8)
        format = PoseFormat::Tum;
    }
    StampedPose p;
    if (format == PoseFormat::Kitti && v.size() == 12) {
      Eigen::Matrix3d r;
      r << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
      // Tolerate the rounding of printed matrices, not a wrong layout or a mirror (det -1,
      // which would turn every scan inside out).
      if (!(r * r.transpose()).isApprox(Eigen::Matrix3d::Identity(), 1e-3) ||
          !(r.determinant() > 0))
        throw PoseFileError(where() + ": the 3x3 block is not a rotation");
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
      p.pose.linear() = svd.matrixU() * svd.matrixV().transpose();  // re-orthonormalised
      p.pose.translation() = Eigen::Vector3d(v[3], v[7], v[11]);
      p.time = double(poses.size());
    } else if (format == PoseFormat::Tum && v.size() == 8) {
      try {
        p.pose = poseFromTranslationQuaternion(&v[1], v[4], v[5], v[6], v[7]);
      } catch (const std::invalid_argument& e) {
        throw PoseFileError(where() + ": " + e.what());
      }
      p.time = v[0];
    } else if (format == PoseFormat::Auto) {
      throw PoseFileError(where() + ": expected 12 numbers (KITTI) or 8 (TUM), found " +
                          std::to_string(v.size()));
    } else {
      throw PoseFileError(where() + ": expected " + formatName(format) +
                          (guessed ? " as the first line, found " : ", found ") +
                          std::to_string(v.size()) + " numbers");
    }
    poses.push_back(p);
  }
  if (poses.empty()) throw PoseFileError("pose file " + path + ": no poses");
  if (used) *used = format;
  return poses;
}

}  // namespace ndtom::io
