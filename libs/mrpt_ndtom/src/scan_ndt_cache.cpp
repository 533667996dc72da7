#include "scan_ndt_cache.h"

#include <mrpt/poses/CPose3D.h>

namespace mrpt_ndtom::detail {

ScanNdtKey ScanNdtKey::of(const mrpt::obs::CObservation& obs) {
  ScanNdtKey key;
  key.observation = &obs;
  key.type = typeid(obs);
  key.stamp = obs.timestamp;
  mrpt::poses::CPose3D pose;
  obs.getSensorPose(pose);
  const auto& rotation = pose.getRotationMatrix();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) key.sensor_pose[size_t(4 * r + c)] = rotation(r, c);
    key.sensor_pose[size_t(4 * r + 3)] = pose.m_coords[r];
  }
  return key;
}

bool ScanNdtKey::operator==(const ScanNdtKey& o) const {
  return observation == o.observation && type == o.type && stamp == o.stamp &&
         sensor_pose == o.sensor_pose && cell_size == o.cell_size && min_range == o.min_range &&
         max_range == o.max_range && max_gaussians == o.max_gaussians &&
         min_eigen_ratio == o.min_eigen_ratio && min_eigen_abs == o.min_eigen_abs;
}

std::shared_ptr<const ndtom::ScanNdt> ScanNdtCache::get(
    const ScanNdtKey& key, const std::function<ndtom::ScanNdt()>& build) const {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const Entry& e : entries_)
      if (e.ndt && e.key == key) return e.ndt;
  }
  auto ndt = std::make_shared<const ndtom::ScanNdt>(build());
  std::lock_guard<std::mutex> lock(mutex_);
  entries_[next_] = {key, ndt};
  next_ = (next_ + 1) % kEntries;
  return ndt;
}

}  // namespace mrpt_ndtom::detail
