// One registration system under test: it holds its own map of the MapScans (built when it is
// made, untimed) and its own copy of the held-out scans in its own point type (converted
// untimed), and registers a held-out scan from a guess (the timed call).
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "ndtom/registration/registration.h"

namespace ndtom::regbench {

/// What one registration returned.
struct Attempt {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< sensor -> world
  /// The system's own verdict, where it gives a meaningful one (NdtRegistration).
  std::optional<bool> converged;
  std::string failure;  ///< why not converged, if the system says
  /// NdtRegistration's finest-level score per scan item and matched fraction, on which its
  /// verdict rests.
  std::optional<double> score, matched_fraction;
  std::vector<LevelReport> levels;  ///< NdtRegistration's pyramid levels, coarse to fine
};

class RegistrationSystem {
 public:
  virtual ~RegistrationSystem() = default;

  /// "ndtom-p2d/t2", "pcl-gicp", ...
  virtual std::string label() const = 0;
  /// The settings, as one line of text for the summary.
  virtual std::string settings() const = 0;
  /// Takes the held-out scans (sensor frame), index = position in `scans`; untimed.
  virtual void setScans(const std::vector<const std::vector<Eigen::Vector3d>*>& scans) = 0;
  /// Registers held-out scan `scan` from `guess` (sensor -> world); the timed call. Everything
  /// the system does to the scan (filters, sampling) happens here.
  virtual Attempt align(size_t scan, const Eigen::Isometry3d& guess) = 0;
};

}  // namespace ndtom::regbench
