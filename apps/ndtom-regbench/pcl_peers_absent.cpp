// The PCL peers in a build without PCL: none.
#include <stdexcept>

#include "pcl_peers.h"

namespace ndtom::regbench {

bool pclAvailable() {
  return false;
}

std::string pclVersion() {
  return {};
}

std::unique_ptr<RegistrationSystem> makePclNdt(const MapScans&) {
  throw std::logic_error("pcl-ndt: this build has no PCL");
}

std::unique_ptr<RegistrationSystem> makePclGicp(const MapScans&) {
  throw std::logic_error("pcl-gicp: this build has no PCL");
}

}  // namespace ndtom::regbench
