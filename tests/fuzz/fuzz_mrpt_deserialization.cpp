// Fuzz target: CNDTOccupancyMap read from an MRPT archive (how MRPT loads maps and how
// rbpf-slam copies its particles). Any input either gives a map that re-serializes to an
// archive reading back to the same bytes and that works (insertion, likelihood, drawing), or
// is rejected with a std::exception that leaves the map unchanged (unless only MRPT's end
// flag after the object is wrong). Crashes, leaks and sanitizer reports are failures.
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "mrpt_ndtom/CNDTOccupancyMap.h"

using mrpt_ndtom::CNDTOccupancyMap;

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

std::vector<uint8_t> serialize(const CNDTOccupancyMap& map) {
  mrpt::io::CMemoryStream buffer;
  mrpt::serialization::archiveFrom(buffer) << map;
  const auto* raw = static_cast<const uint8_t*>(buffer.getRawBufferData());
  return {raw, raw + buffer.getTotalBytesCount()};
}

// True if the archive starts with the header MRPT writes for this class (new format: 0x80 |
// name length, the name), so reading it through the class registry makes one of ours.
bool namesThisClass(const uint8_t* data, size_t size) {
  const std::string name = "mrpt_ndtom::CNDTOccupancyMap";
  return size > name.size() && data[0] == (0x80 | name.size()) &&
         std::memcmp(data + 1, name.data(), name.size()) == 0;
}

// A map read successfully must be usable; option checks may still reject an observation.
void exercise(CNDTOccupancyMap& map) {
  map.setMinLoggingLevel(mrpt::system::LVL_ERROR);  // no warnings about rejected points
  map.asString();
  mrpt::obs::CObservation2DRangeScan scan;
  scan.aperture = 3.0f;
  scan.resizeScan(9);
  for (size_t i = 0; i < 9; ++i) {
    scan.setScanRange(i, 0.5f + 0.7f * float(i));
    scan.setScanRangeValidity(i, true);
  }
  map.computeObservationLikelihood(scan, mrpt::poses::CPose3D());
  // And with the other likelihood method, which builds other structures from the map.
  using Method = CNDTOccupancyMap::TLikelihoodMethod;
  map.likelihoodOptions.likelihood_method =
      map.likelihoodOptions.likelihood_method == Method::Points ? Method::NdtMcl : Method::Points;
  map.computeObservationLikelihood(scan, mrpt::poses::CPose3D());
  mrpt::opengl::CSetOfObjects drawing;
  map.getVisualizationInto(drawing);
  map.insertPoints({{1.0, 0.2, 0.3}, {0.0, 0.0, 0.0}, {-2.5, 1.0, 0.1}}, {0.1, 0.1, 0.1});
}

// Fuzzing means nothing if every input is rejected: a map with data must read back.
bool readsBackAMap() {
  CNDTOccupancyMap map(0.5);
  map.insertPoints({{1.0, 0.2, 0.3}, {1.1, 0.2, 0.35}, {1.2, 0.3, 0.3}, {-1, 2, 0}}, {0, 0, 0});
  const std::vector<uint8_t> bytes = serialize(map);
  mrpt::io::CMemoryStream stream;
  stream.assignMemoryNotOwn(bytes.data(), bytes.size());
  CNDTOccupancyMap read;
  try {
    mrpt::serialization::archiveFrom(stream).ReadObject(&read);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_mrpt_deserialization: a valid archive fails: %s\n", e.what());
    return false;
  }
  return serialize(read) == bytes && read.ndtMap().numGaussians() == 1;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bool ready = readsBackAMap();
  check(ready);
  CNDTOccupancyMap map(0.5);
  const std::vector<uint8_t> before = serialize(map);
  mrpt::io::CMemoryStream stream;
  stream.assignMemoryNotOwn(data, size);
  try {
    mrpt::serialization::archiveFrom(stream).ReadObject(&map);
  } catch (const std::exception& e) {
    // Unchanged, unless the map itself was fine and only the end flag MRPT reads after it
    // is wrong (that check comes after serializeFrom, which has already replaced the map).
    const std::string what = e.what();
    check(serialize(map) == before || what.find("end-flag missing") != std::string::npos);
    return 0;
  }

  // Accepted: the same map comes back from its own archive, also through the registry.
  const std::vector<uint8_t> bytes = serialize(map);
  mrpt::io::CMemoryStream again_stream;
  again_stream.assignMemoryNotOwn(bytes.data(), bytes.size());
  CNDTOccupancyMap again;
  mrpt::serialization::archiveFrom(again_stream).ReadObject(&again);
  check(serialize(again) == bytes);
  if (namesThisClass(data, size)) {
    stream.Seek(0);
    const auto read = mrpt::serialization::archiveFrom(stream).ReadObject<CNDTOccupancyMap>();
    check(read && serialize(*read) == bytes);
  }

  try {
    exercise(map);
  } catch (const std::exception&) {
  }
  return 0;
}
