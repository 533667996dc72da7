// MRPT's SENA log (Debian's mrpt-common): 225 real 2D laser scans with odometry, one loop,
// and MRPT's reference map of it (its frames carry the log's time stamps).
#pragma once

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace ndtom::testing {

inline const std::string kSenaLog =
    std::string(MRPT_DATASETS) + "/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
inline const std::string kSenaReference =
    std::string(MRPT_DATASETS) + "/malaga-cs-fac-building.simplemap.gz";

struct ActionFrame {
  mrpt::obs::CActionCollection::Ptr actions;
  mrpt::obs::CSensoryFrame::Ptr frame;
};

/// The first `count` action/frame pairs (all if 0).
inline std::vector<ActionFrame> readSena(size_t count = 0) {
  mrpt::io::CFileGZInputStream file(kSenaLog);
  auto archive = mrpt::serialization::archiveFrom(file);
  std::vector<ActionFrame> pairs;
  mrpt::obs::CActionCollection::Ptr actions;
  mrpt::obs::CSensoryFrame::Ptr frame;
  mrpt::obs::CObservation::Ptr observation;
  size_t entry = 0;
  while ((count == 0 || pairs.size() < count) &&
         mrpt::obs::CRawlog::getActionObservationPairOrObservation(archive, actions, frame,
                                                                   observation, entry))
    if (actions && frame) pairs.push_back({actions, frame});
  return pairs;
}

/// MRPT's reference poses of the log's scans, by time stamp in ms.
inline std::map<long, mrpt::poses::CPose3D> senaReferencePoses() {
  mrpt::maps::CSimpleMap reference;
  std::map<long, mrpt::poses::CPose3D> by_time;
  if (!reference.loadFromFile(kSenaReference)) return by_time;
  for (const auto& [pose, frame] : reference)
    by_time[std::lround(mrpt::Clock::toDouble((*frame->begin())->timestamp) * 1e3)] =
        pose->getMeanVal();
  return by_time;
}

inline bool senaAvailable() {
  return std::filesystem::exists(kSenaLog);
}

}  // namespace ndtom::testing
