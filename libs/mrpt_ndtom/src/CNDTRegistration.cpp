// CNDTRegistration: MRPT's alignment interface over ndtom::NdtRegistration.
#include "mrpt_ndtom/CNDTRegistration.h"

#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <Eigen/Geometry>
#include <chrono>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "mrpt_ndtom/observation_points.h"
#include "mrpt_ndtom/points_map.h"

namespace mrpt_ndtom {
namespace {

mrpt::poses::CPose3D toPose(const Eigen::Isometry3d& t) {
  mrpt::math::CMatrixDouble44 m;
  m.asEigen() = t.matrix();
  return mrpt::poses::CPose3D(m);
}

}  // namespace

mrpt::math::CMatrixDouble66 toMrptPoseCovariance(const ndtom::Matrix6d& covariance,
                                                const mrpt::poses::CPose3D& pose) {
  // A change d of (yaw, pitch, roll) turns R = Rz·Ry·Rx by ω = E·d in the map frame, E's
  // columns: z, Rz·y, Rz·Ry·x. So d = E⁻¹ω, and the translation is the same in both.
  const double yaw = pose.yaw(), pitch = pose.pitch();
  const Eigen::Matrix3d rz = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d ry =
      Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).toRotationMatrix();
  Eigen::Matrix3d e;
  e.col(0) = Eigen::Vector3d::UnitZ();
  e.col(1) = rz * Eigen::Vector3d::UnitY();
  e.col(2) = rz * ry * Eigen::Vector3d::UnitX();
  ndtom::Matrix6d j = ndtom::Matrix6d::Identity();
  j.bottomRightCorner<3, 3>() = e.inverse();  // singular only at pitch = ±90° (gimbal lock)
  mrpt::math::CMatrixDouble66 out;
  out.asEigen() = j * covariance * j.transpose();
  return out;
}

ndtom::RegistrationResult CNDTRegistration::align(
    const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
    const mrpt::poses::CPose3D& guess, bool planar,
    mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> info) {
  const auto start = std::chrono::steady_clock::now();
  const auto* map = dynamic_cast<const CNDTOccupancyMap*>(m1);
  if (!map) THROW_EXCEPTION("CNDTRegistration: the reference map (m1) must be a CNDTOccupancyMap");
  const mrpt::maps::CPointsMap* points = asPointsMap(m2);
  if (!points) THROW_EXCEPTION("CNDTRegistration: the map to align (m2) must be a CPointsMap");

  ndtom::RegistrationOptions o = options.core;
  o.planar = o.planar || planar;
  ndtom::RegistrationResult result;
  try {
    m_registration.setOptions(o);
    result = m_registration.align(map->ndtMap(), pointsOf(*points), toIsometry(guess));
  } catch (const std::invalid_argument& e) {
    THROW_EXCEPTION(std::string("CNDTRegistration: ") + e.what());
  }
  if (!result.converged) logStr(mrpt::system::LVL_WARN, "not converged: " + result.failure);
  if (info) {
    info->get().executionTime =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (auto* ours = dynamic_cast<TReturnInfo*>(&info->get())) ours->result = result;
  }
  return result;
}

mrpt::poses::CPose3DPDF::Ptr CNDTRegistration::Align3DPDF(
    const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
    const mrpt::poses::CPose3DPDFGaussian& initialEstimationPDF,
    mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> outInfo) {
  const ndtom::RegistrationResult r = align(m1, m2, initialEstimationPDF.mean, false, outInfo);
  const mrpt::poses::CPose3D pose = toPose(r.pose);
  return mrpt::poses::CPose3DPDFGaussian::Create(pose, toMrptPoseCovariance(r.covariance, pose));
}

mrpt::poses::CPosePDF::Ptr CNDTRegistration::AlignPDF(
    const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
    const mrpt::poses::CPosePDFGaussian& initialEstimationPDF,
    mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> outInfo) {
  const mrpt::poses::CPose3D guess(initialEstimationPDF.mean);
  const ndtom::RegistrationResult r = align(m1, m2, guess, true, outInfo);
  const mrpt::poses::CPose3D pose = toPose(r.pose);
  const mrpt::math::CMatrixDouble66 c = toMrptPoseCovariance(r.covariance, pose);
  mrpt::math::CMatrixDouble33 planar;  // (x, y, yaw) of (x, y, z, yaw, pitch, roll)
  const int keep[3] = {0, 1, 3};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) planar(i, j) = c(keep[i], keep[j]);
  return mrpt::poses::CPosePDFGaussian::Create(mrpt::poses::CPose2D(pose), planar);
}

}  // namespace mrpt_ndtom
