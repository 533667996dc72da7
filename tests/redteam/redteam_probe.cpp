// The red team's probe (scripts/redteam.sh): runs one library entry point on one input in its
// own process, so that the harness sees crashes, time and peak memory per input. Uses only
// calls that 6f42e33 has too, so that the same probe measures the code before issue #17.
//
//   redteam_probe load-ndtom FILE | load-ndtommap FILE | parse-pcd FILE | poses FILE |
//                 depth FILE | mrpt-read FILE | writable-insert RES X Y Z OUT |
//                 writable-setcell I J K LOGODDS N MEAN OUT | saturate N
//
// Exit status: 0 accepted (one line on stdout says what), 1 refused with an exception (its
// message on stderr), 4 written but not loadable (data loss), 5 a wrong value seen.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom/files/map_io.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"
#include "ndtom_io/tum_rgbd.h"

namespace {

int usage() {
  std::fprintf(stderr, "redteam_probe: unknown command (see the source)\n");
  return 64;
}

// Saved to `path` and loaded back: 0, or 4 if the file written cannot be loaded.
int roundTrip(const ndtom::NdtMap& map, const std::string& path) {
  ndtom::saveMap(map, path);
  try {
    const ndtom::NdtMap loaded = ndtom::loadMap(path);
    if (ndtom::encodeMap(loaded) != ndtom::encodeMap(map)) {
      std::printf("loaded, but different\n");
      return 4;
    }
  } catch (const std::exception& e) {
    std::printf("saved, not loadable: %s\n", e.what());
    return 4;
  }
  std::printf("ok cells=%zu\n", map.numCells());
  return 0;
}

int run(int argc, char** argv) {
  if (argc < 3) return usage();
  const std::string command = argv[1], file = argv[2];
  if (command == "load-ndtom") {
    const ndtom::NdtMap map = ndtom::loadMap(file);
    std::printf("ok cells=%zu gaussians=%zu\n", map.numCells(), map.numGaussians());
  } else if (command == "load-ndtommap") {
    mrpt::io::CFileGZInputStream in(file);
    auto object = mrpt::serialization::archiveFrom(in).ReadObject();
    const auto map = std::dynamic_pointer_cast<mrpt_ndtom::CNDTOccupancyMap>(object);
    if (!map) throw std::runtime_error("not a CNDTOccupancyMap");
    std::printf("ok cells=%zu\n", map->ndtMap().numCells());
  } else if (command == "parse-pcd") {
    std::printf("ok points=%zu\n", ndtom::io::readPcd(file).points.size());
  } else if (command == "poses") {
    const auto poses = ndtom::io::readPoseFile(file);
    double lowest_det = 1;
    for (const auto& p : poses) lowest_det = std::min(lowest_det, p.pose.linear().determinant());
    std::printf("ok poses=%zu det=%g\n", poses.size(), lowest_det);
    if (!(lowest_det > 0)) return 5;  // a mirror was taken for a pose
  } else if (command == "depth") {
    const auto points = ndtom::io::readDepthImagePoints(file, ndtom::io::DepthCamera{});
    std::printf("ok points=%zu\n", points.size());
  } else if (command == "mrpt-read") {  // MRPT's own reader alone: who crashes, MRPT or us?
    mrpt::io::CFileGZInputStream in(file);
    auto archive = mrpt::serialization::archiveFrom(in);
    size_t objects = 0;
    try {
      for (;; ++objects) archive.ReadObject();
    } catch (const mrpt::serialization::CExceptionEOF&) {
    }
    std::printf("ok objects=%zu\n", objects);
  } else if (command == "writable-insert" && argc == 7) {
    ndtom::MapOptions o;
    o.resolution = std::atof(argv[2]);
    o.scan.max_range = 10 * o.resolution;
    ndtom::NdtMap map(o);
    const Eigen::Vector3d p(std::atof(argv[3]), std::atof(argv[4]), std::atof(argv[5]));
    const double step = 5 * o.resolution;
    const Eigen::Vector3d origin = p - Eigen::Vector3d(p.x() > 0 ? step : -step, 0, 0);
    const auto report = map.insertScan(
        {p, p + Eigen::Vector3d(0, 1e-3, 0), p + Eigen::Vector3d(0, 0, 1e-3)}, origin);
    if (report.pointsUsed() == 0) throw std::runtime_error("all points rejected");
    return roundTrip(map, argv[6]);
  } else if (command == "writable-setcell" && argc == 9) {
    ndtom::NdtMap map;
    ndtom::CellStats stats;
    stats.n = uint32_t(std::atoi(argv[6]));
    stats.relative_mean = Eigen::Vector3d::Constant(std::atof(argv[7]));
    if (stats.n > 1) stats.scatter = Eigen::Matrix3d::Identity() * 1e-4;
    map.setCell(
        {int32_t(std::atol(argv[2])), int32_t(std::atol(argv[3])), int32_t(std::atol(argv[4]))},
        float(std::atof(argv[5])), stats);
    return roundTrip(map, argv[8]);
  } else if (command == "saturate") {
    // Two maps of one cell with N points each, merged; and 8 such cells coarsened into one.
    const uint32_t n = uint32_t(std::strtoul(argv[2], nullptr, 10));
    ndtom::CellStats s;
    s.n = n;
    s.scatter = Eigen::Matrix3d::Identity() * 1e-4;
    ndtom::NdtMap a, b;
    a.setCell({0, 0, 0}, 1.f, s);
    b.setCell({0, 0, 0}, 1.f, s);
    for (int i = 1; i < 8; ++i) a.setCell({i & 1, (i >> 1) & 1, (i >> 2) & 1}, 1.f, s);
    const ndtom::NdtMap coarse = a.coarsened(2);
    a.merge(b);
    // A count that wrapped to 0 leaves no statistics at all.
    const auto* m = a.cell({0, 0, 0})->stats;
    const auto* k = coarse.cell({0, 0, 0})->stats;
    const uint32_t merged = m ? m->n : 0, coarsened = k ? k->n : 0;
    std::printf("ok merged=%u coarsened=%u\n", merged, coarsened);
    if (merged < n || coarsened < n) return 5;  // the count wrapped
  } else {
    return usage();
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "redteam_probe: %s\n", ndtom::apps::oneLineMessage(e).c_str());
    return 1;
  }
}
