#include "pcd_to_rawlog.h"

#include <mrpt/io/CStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>

#include "ndtom_apps/option_values.h"
#include "ndtom_apps/output_files.h"
#include "ndtom_apps/scan_source.h"

namespace fs = std::filesystem;

namespace ndtom::rawlog {
namespace {

using apps::InputError;

mrpt::poses::CPose3D toPose(const Eigen::Isometry3d& t) {
  mrpt::math::CMatrixDouble44 m;
  m.asEigen() = t.matrix();
  return mrpt::poses::CPose3D(m);
}

void checkRange(const char* option, const ScanRange& r, size_t scans, const std::string& folder) {
  if (r.last >= scans)
    throw apps::UsageError(std::string(option) + " " + std::to_string(r.first) + ":" +
                           std::to_string(r.last) + ": " + folder + " has scans 0 to " +
                           std::to_string(scans - 1));
}

// MRPT's archives into a file written through ndtom's sink (which names the file and why a
// write failed). MRPT turns a failed write into "Cannot write bytes to stream!", naming
// nothing: the sink's message is kept here for the caller to report.
class SinkStream : public mrpt::io::CStream {
 public:
  explicit SinkStream(const ndtom::FileSink& sink) : sink_(sink) {}
  size_t Read(void*, size_t) override { throw std::logic_error("SinkStream: write only"); }
  size_t Write(const void* data, size_t size) override {
    if (!error_.empty()) return 0;
    try {
      sink_(data, size);
    } catch (const std::exception& e) {
      error_ = e.what();
      return 0;
    }
    written_ += size;
    return size;
  }
  uint64_t Seek(int64_t, TSeekOrigin) override { throw std::logic_error("SinkStream: no seek"); }
  uint64_t getTotalBytesCount() const override { return written_; }
  uint64_t getPosition() const override { return written_; }
  const std::string& error() const { return error_; }  ///< empty while writes succeed

 private:
  const ndtom::FileSink& sink_;
  uint64_t written_ = 0;
  std::string error_;
};

}  // namespace

mrpt::obs::CObservationPointCloud::Ptr pointCloudObservation(
    const std::vector<Eigen::Vector3d>& points, double time) {
  auto cloud = mrpt::maps::CSimplePointsMap::Create();
  cloud->reserve(points.size());
  for (const Eigen::Vector3d& p : points)
    if (p.allFinite()) cloud->insertPointFast(float(p.x()), float(p.y()), float(p.z()));
  auto obs = mrpt::obs::CObservationPointCloud::Create();
  obs->pointcloud = cloud;
  obs->sensorLabel = "LIDAR";
  obs->timestamp = mrpt::Clock::fromDouble(time);
  obs->sensorPose = mrpt::poses::CPose3D();
  return obs;
}

mrpt::obs::CActionRobotMovement3D odometryAction(const mrpt::poses::CPose3D& increment,
                                                 const OdometryNoise& noise, std::mt19937_64& rng,
                                                 double time) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double sa = noise.std_deg * M_PI / 180;
  // The pose PDF samples (x, y, z, yaw, pitch, roll) additively: add the noise the same way.
  mrpt::math::CVectorFixedDouble<6> v;
  for (int i = 0; i < 6; ++i) v[i] = increment[i] + (i < 3 ? noise.std_xyz : sa) * gauss(rng);
  mrpt::math::CMatrixDouble66 cov;
  cov.setZero();
  for (int i = 0; i < 6; ++i) cov(i, i) = i < 3 ? noise.std_xyz * noise.std_xyz : sa * sa;

  mrpt::obs::CActionRobotMovement3D action;
  action.estimationMethod = mrpt::obs::CActionRobotMovement3D::emOdometry;
  action.poseChange = mrpt::poses::CPose3DPDFGaussian(
      mrpt::poses::CPose3D(v[0], v[1], v[2], v[3], v[4], v[5]), cov);
  action.rawOdometryIncrementReading = action.poseChange.mean;
  action.timestamp = mrpt::Clock::fromDouble(time);
  return action;
}

ConversionReport convertFolder(const RawlogOptions& o, apps::Progress& progress) {
  apps::SourceSettings settings;
  settings.input = o.folder;
  settings.format = apps::InputFormat::PcdFolder;
  settings.decimation = o.decimation;
  auto source = apps::openPcdFolder(settings);
  const size_t scans = source->size();
  const ScanRange log = o.log_scans.value_or(ScanRange{0, scans - 1});
  checkRange("--scans", log, scans, o.folder);
  if (o.map_scans) checkRange("--map-scans", *o.map_scans, scans, o.folder);
  const size_t needed = std::max(log.last, o.map_scans ? o.map_scans->last : 0) + 1;
  // KITTI pose files carry no time: times.txt beside them does.
  const std::vector<double> times =
      apps::readScanTimes((fs::path(o.folder) / "times.txt").string(), scans);

  apps::OutputFiles out(o.prefix);
  std::string ground_truth =
      "# time x y z yaw pitch roll (s, m, rad): the scans' reference poses\n";
  mrpt::maps::CSimpleMap simplemap;

  ConversionReport report;
  std::mt19937_64 rng(o.noise.seed);
  std::optional<mrpt::poses::CPose3D> previous;
  progress.start("reading", needed);
  // The rawlog is written as the scans are read; a failed write (a full disk) names the
  // output and why, and leaves no temporary.
  out.write("rawlog", ".rawlog", [&](const ndtom::FileSink& sink) {
    SinkStream rawlog_file(sink);
    auto rawlog = mrpt::serialization::archiveFrom(rawlog_file);
    for (size_t i = 0; i < needed; ++i) {
      const std::optional<apps::Scan> scan = source->next();
      if (!scan) throw InputError(o.folder + ": fewer scans than listed");
      const mrpt::poses::CPose3D pose = toPose(scan->frame_pose);
      const auto obs = pointCloudObservation(apps::pointsInFrame(*scan), times[i]);
      if (log.contains(i)) {
        const mrpt::poses::CPose3D increment = previous ? pose - *previous : mrpt::poses::CPose3D();
        mrpt::obs::CActionCollection actions;
        actions.insert(odometryAction(increment, o.noise, rng, times[i]));
        mrpt::obs::CSensoryFrame frame;
        frame.insert(obs);
        try {
          rawlog << actions << frame;
        } catch (const std::exception&) {
          if (rawlog_file.error().empty()) throw;
          throw std::runtime_error(o.prefix + ".rawlog: writing scan " + std::to_string(i) +
                                   " failed: " + rawlog_file.error());
        }
        previous = pose;
        char line[200];
        std::snprintf(line, sizeof(line), "%.6f %.6f %.6f %.6f %.9f %.9f %.9f\n", times[i],
                      pose.x(), pose.y(), pose.z(), pose.yaw(), pose.pitch(), pose.roll());
        ground_truth += line;
        ++report.log_scans;
        report.log_points += obs->pointcloud->size();
      }
      if (o.map_scans && o.map_scans->contains(i)) {
        auto frame = mrpt::obs::CSensoryFrame::Create();
        frame->insert(obs);
        simplemap.insert(mrpt::poses::CPose3DPDFGaussian::Create(pose), frame);
        ++report.map_scans;
        report.map_points += obs->pointcloud->size();
      }
      progress.update(i + 1, report.log_points + report.map_points);
    }
  });
  out.writeBytes("ground truth", ".gt.txt", ground_truth);
  errno = 0;
  if (o.map_scans && !simplemap.saveToFile(out.stage("simplemap", ".simplemap")))
    throw std::runtime_error(o.prefix + ".simplemap: cannot write" +
                             (errno ? std::string(": ") + std::strerror(errno) : std::string()));
  out.commit();
  for (const auto& f : out.files()) report.files.push_back(f.path);
  return report;
}

}  // namespace ndtom::rawlog
