// CNDTRegistration: NDT scan-to-map registration (ndtom/registration/registration.h) as an MRPT map
// alignment algorithm, swappable with mrpt::slam::CICP wherever a
// CMetricMapsAlignmentAlgorithm is used:
//
//   CNDTRegistration ndt;
//   ndt.options.loadFromConfigFile(ini, "NDTRegistration");
//   CNDTRegistration::TReturnInfo info;
//   auto pdf = ndt.Align3D(&ndtMap, &scanPoints, guess, info);   // pose of the scan in the map
//
// m1 (the reference) is a CNDTOccupancyMap, m2 any CPointsMap in its own frame (a scan in the
// sensor or robot frame). Align3D/Align3DPDF estimate all six degrees of freedom; Align/
// AlignPDF (SE(2)) only x, y and yaw, z = roll = pitch = 0. The result is a Gaussian whose
// mean is the estimate; a failed verdict (TReturnInfo) returns the last estimate with a huge
// covariance. The map's pyramid is kept between calls until the map changes.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/slam/CMetricMapsAlignmentAlgorithm.h>

#include <string>

#include "ndtom/registration/registration.h"

namespace mrpt_ndtom {

class CNDTRegistration : public mrpt::slam::CMetricMapsAlignmentAlgorithm {
 public:
  /// The core's RegistrationOptions as an .ini section (same names, same defaults).
  class TConfigParams : public mrpt::config::CLoadableOptions {
   public:
    /// Throws (naming the section and option) on a bad value.
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;

    ndtom::RegistrationOptions core;
  };
  TConfigParams options;

  struct TReturnInfo : public mrpt::slam::TMetricMapAlignmentResult {
    ndtom::RegistrationResult result;  ///< levels, score, matched fraction, verdict, ...
  };

  CNDTRegistration() { setLoggerName("CNDTRegistration"); }

  /// SE(2): x, y and yaw of m2 in m1 from the mean of `initialEstimationPDF`.
  mrpt::poses::CPosePDF::Ptr AlignPDF(
      const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
      const mrpt::poses::CPosePDFGaussian& initialEstimationPDF,
      mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> outInfo = std::nullopt) override;

  /// SE(3): the pose of m2 in m1 from the mean of `initialEstimationPDF`.
  mrpt::poses::CPose3DPDF::Ptr Align3DPDF(
      const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
      const mrpt::poses::CPose3DPDFGaussian& initialEstimationPDF,
      mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> outInfo = std::nullopt) override;

 private:
  ndtom::RegistrationResult align(const mrpt::maps::CMetricMap* m1,
                                  const mrpt::maps::CMetricMap* m2,
                                  const mrpt::poses::CPose3D& guess, bool planar,
                                  mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> info);

  ndtom::NdtRegistration m_registration;
};

/// A covariance of the registration's parameters (translation, rotation vector about the
/// sensor in the map frame) as MRPT's CPose3DPDFGaussian holds it: (x, y, z, yaw, pitch, roll)
/// of `pose`.
mrpt::math::CMatrixDouble66 toMrptPoseCovariance(const ndtom::Matrix6d& covariance,
                                                const mrpt::poses::CPose3D& pose);

}  // namespace mrpt_ndtom
