// The scan NDTs that the NdtMcl likelihood scores, kept across the particles of a filter
// update. MRPT's particle filters call computeObservationLikelihood() once per particle with
// the same observation (PF_implementations.h, pfStandardProposal: one call per particle, in
// one loop), and building a lidar scan's NDT costs as much as scoring hundreds of particles.
//
// An entry is found by the observation's address, type, time stamp and sensor pose, and by
// everything the NDT is built with. An observation changed in place, keeping all of these,
// is scored with its old NDT: MRPT's programs never do that (each observation read from a
// rawlog is a new object with its own time stamp).
//
// Threading: get() may run concurrently (pf-localization runs its experiment repetitions on
// several threads over one map). The mutex guards only the lookup and the store; a missing
// NDT is built outside it, so two threads may build the same one once.
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation.h>

#include <array>
#include <functional>
#include <memory>
#include <mutex>
#include <typeindex>

#include "ndtom/localization/ndt_mcl.h"

namespace mrpt_ndtom::detail {

struct ScanNdtKey {
  const void* observation = nullptr;
  std::type_index type = typeid(void);
  mrpt::Clock::time_point stamp;
  std::array<double, 12> sensor_pose{};  ///< the 3×4 [R|t]
  double cell_size = 0, min_range = 0, max_range = 0;
  size_t max_gaussians = 0;
  double min_eigen_ratio = 0, min_eigen_abs = 0;

  /// The parts that come from `obs`; the caller fills in the build settings.
  static ScanNdtKey of(const mrpt::obs::CObservation& obs);
  bool operator==(const ScanNdtKey& o) const;
};

class ScanNdtCache {
 public:
  ScanNdtCache() = default;
  ScanNdtCache(const ScanNdtCache&) = delete;
  ScanNdtCache& operator=(const ScanNdtCache&) = delete;

  /// The NDT stored under `key`, or `build()`'s result, stored in place of the oldest entry.
  std::shared_ptr<const ndtom::ScanNdt> get(const ScanNdtKey& key,
                                            const std::function<ndtom::ScanNdt()>& build) const;

 private:
  // A few entries: repetitions running side by side each have their current observation.
  static constexpr size_t kEntries = 4;
  struct Entry {
    ScanNdtKey key;
    std::shared_ptr<const ndtom::ScanNdt> ndt;
  };
  mutable std::mutex mutex_;
  mutable std::array<Entry, kEntries> entries_;
  mutable size_t next_ = 0;
};

}  // namespace mrpt_ndtom::detail
