// pcl-ndt and pcl-gicp: PCL 1.13's NormalDistributionsTransform and
// GeneralizedIterativeClosestPoint, built only when CMake finds PCL (an optional,
// benchmark-only dependency: scripts/setup.sh --with-pcl). No PCL type appears here.
#pragma once

#include <memory>
#include <string>

#include "lidar_sequence.h"
#include "registration_system.h"

namespace ndtom::regbench {

/// Whether this build has the PCL peers, and PCL's version ("1.13.0"; empty without).
bool pclAvailable();
std::string pclVersion();

/// Throw std::logic_error in a build without PCL.
std::unique_ptr<RegistrationSystem> makePclNdt(const MapScans& map);
std::unique_ptr<RegistrationSystem> makePclGicp(const MapScans& map);

}  // namespace ndtom::regbench
