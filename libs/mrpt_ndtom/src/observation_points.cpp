#include "mrpt_ndtom/observation_points.h"

#include <mrpt/maps/CPointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationVelodyneScan.h>

#include <cmath>
#include <stdexcept>

namespace mrpt_ndtom {
namespace {

using Eigen::Vector3d;
using mrpt::obs::CObservation;

// Appends every `step`-th point of parallel float arrays (sensor frame), skipping the
// (0,0,0) that MRPT uses for "no reading".
template <class Vec>
void appendSensorPoints(const Vec& xs, const Vec& ys, const Vec& zs, uint32_t step,
                        const Eigen::Isometry3d& sensor_to_world, std::vector<Vector3d>& out) {
  const size_t n = std::min({xs.size(), ys.size(), zs.size()});
  out.reserve(out.size() + n / step + 1);
  for (size_t i = 0; i < n; i += step) {
    if (xs[i] == 0 && ys[i] == 0 && zs[i] == 0) continue;
    out.push_back(sensor_to_world * Vector3d(xs[i], ys[i], zs[i]));
  }
}

void fromScan2D(const mrpt::obs::CObservation2DRangeScan& o, uint32_t step,
                const Eigen::Isometry3d& sensor_to_world, std::vector<Vector3d>& out) {
  for (size_t i = 0; i < o.getScanSize(); i += step) {
    if (!o.getScanRangeValidity(i)) continue;
    const double r = o.getScanRange(i), a = o.getScanAngle(i);
    out.push_back(sensor_to_world * Vector3d(r * std::cos(a), r * std::sin(a), 0.0));
  }
}

// As CObservation3DRangeScan::unprojectInto() computes it (+x forward, +y left, +z up), with
// MRPT's own per-pixel table of undistorted ray directions, but without writing into the
// observation (unprojectInto() resizes its point buffers: not safe for concurrent use).
void fromDepthImage(const mrpt::obs::CObservation3DRangeScan& o, uint32_t step,
                    const Eigen::Isometry3d& sensor_to_world, std::vector<Vector3d>& out) {
  const auto& image = o.rangeImage;
  if (image.cols() != int(o.cameraParams.ncols) || image.rows() != int(o.cameraParams.nrows))
    throw std::invalid_argument(
        "CObservation3DRangeScan: range image size differs from cameraParams");
  const auto& lut = o.get_unproj_lut();  // thread-safe, cached by MRPT per calibration
  const int width = image.cols();
  for (int r = 0; r < image.rows(); r += int(step))
    for (int c = 0; c < width; c += int(step)) {
      const uint16_t raw = image(r, c);
      if (raw == 0) continue;
      const size_t i = size_t(r) * size_t(width) + size_t(c);
      const double range = raw * double(o.rangeUnits);  // depth, or distance if !range_is_depth
      out.push_back(sensor_to_world *
                    Vector3d(range * lut.Kxs[i], range * lut.Kys[i], range * lut.Kzs[i]));
    }
}

void fromScan3D(const mrpt::obs::CObservation3DRangeScan& o, const TPointExtractionOptions& options,
                const Eigen::Isometry3d& sensor_to_world, std::vector<Vector3d>& out) {
  if (o.rangeImage_isExternallyStored() || o.points3D_isExternallyStored()) o.load();
  if (o.hasRangeImage)
    fromDepthImage(o, options.decimation_3d_range, sensor_to_world, out);
  else if (o.hasPoints3D)
    appendSensorPoints(o.points3D_x, o.points3D_y, o.points3D_z, options.decimation,
                       sensor_to_world, out);
}

// Collects the points generatePointCloud() makes, without touching the observation's own
// point_cloud field.
struct VelodynePoints : mrpt::obs::CObservationVelodyneScan::PointCloudStorageWrapper {
  std::vector<float> x, y, z;
  void add_point(float px, float py, float pz, uint8_t, const mrpt::system::TTimeStamp&, float,
                 uint16_t) override {
    x.push_back(px);
    y.push_back(py);
    z.push_back(pz);
  }
};

void fromVelodyne(const mrpt::obs::CObservationVelodyneScan& o, uint32_t step,
                  const Eigen::Isometry3d& sensor_to_world, std::vector<Vector3d>& out) {
  if (o.point_cloud.size() > 0) {
    appendSensorPoints(o.point_cloud.x, o.point_cloud.y, o.point_cloud.z, step, sensor_to_world,
                       out);
    return;
  }
  VelodynePoints points;
  // generatePointCloud() is not const in MRPT 2.5.8, but with an external storage wrapper
  // it only reads the raw packets and the calibration.
  const_cast<mrpt::obs::CObservationVelodyneScan&>(o).generatePointCloud(points);
  appendSensorPoints(points.x, points.y, points.z, step, sensor_to_world, out);
}

}  // namespace

Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.matrix() = pose.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen();
  return t;
}

bool isSupportedObservation(const CObservation& obs) {
  using namespace mrpt::obs;
  return IS_CLASS(obs, CObservation2DRangeScan) || IS_CLASS(obs, CObservation3DRangeScan) ||
         IS_CLASS(obs, CObservationPointCloud) || IS_CLASS(obs, CObservationVelodyneScan);
}

std::optional<ObservationPoints> observationPoints(const CObservation& obs,
                                                   const mrpt::poses::CPose3D& robotPose,
                                                   const TPointExtractionOptions& options) {
  using namespace mrpt::obs;
  if (options.decimation < 1 || options.decimation_3d_range < 1)
    throw std::invalid_argument("observationPoints: decimation must be >= 1");
  if (!isSupportedObservation(obs)) return std::nullopt;

  mrpt::poses::CPose3D sensor_pose;
  obs.getSensorPose(sensor_pose);
  const Eigen::Isometry3d sensor_to_world = toIsometry(robotPose + sensor_pose);
  ObservationPoints result;
  result.sensor_origin = sensor_to_world.translation();
  auto& out = result.points_world;
  if (const auto* scan = dynamic_cast<const CObservation2DRangeScan*>(&obs)) {
    fromScan2D(*scan, options.decimation, sensor_to_world, out);
  } else if (const auto* scan3d = dynamic_cast<const CObservation3DRangeScan*>(&obs)) {
    fromScan3D(*scan3d, options, sensor_to_world, out);
  } else if (const auto* cloud = dynamic_cast<const CObservationPointCloud*>(&obs)) {
    if (cloud->isExternallyStored()) cloud->load();
    if (cloud->pointcloud)
      appendSensorPoints(
          cloud->pointcloud->getPointsBufferRef_x(), cloud->pointcloud->getPointsBufferRef_y(),
          cloud->pointcloud->getPointsBufferRef_z(), options.decimation, sensor_to_world, out);
  } else if (const auto* velodyne = dynamic_cast<const CObservationVelodyneScan*>(&obs)) {
    fromVelodyne(*velodyne, options.decimation, sensor_to_world, out);
  }
  return result;
}

}  // namespace mrpt_ndtom
