// The parts of the CMetricMap interface MRPT code calls beyond insertion and likelihood, each
// against an independent computation: 2D ICP on real laser scans (and MRPT's ICP with its own
// points map as the oracle), the matching ratio against another NDT map, voxels (counted cell
// by cell, and against MRPT's COccupancyGridMap3D on the same scans), the bounding box, the
// nearest Gaussian in the plane, point occupancy and ray casting.
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap3D.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/slam/CICP.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <set>

#include "mrpt_ndtom/CNDTOccupancyMap.h"

using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;
using mrpt_ndtom::CNDTOccupancyMap;

namespace {

const std::string kDatasets = MRPT_DATASETS;

struct Keyframe {
  CPose3D pose;
  mrpt::obs::CObservation2DRangeScan::Ptr scan;
};

// The first `count` keyframes of MRPT's Málaga simplemap (2D laser scans with SLAM poses).
std::vector<Keyframe> malagaKeyframes(size_t count) {
  mrpt::maps::CSimpleMap simplemap;
  if (!simplemap.loadFromFile(kDatasets + "/malaga-cs-fac-building.simplemap.gz")) return {};
  std::vector<Keyframe> frames;
  for (size_t k = 0; k < simplemap.size() && frames.size() < count; ++k) {
    const auto& [pose_pdf, frame] = simplemap.get(k);
    for (const auto& obs : *frame)
      if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs)) {
        frames.push_back({pose_pdf->getMeanVal(), scan});
        break;
      }
  }
  return frames;
}

// The scan's points in the robot frame, every reading kept.
mrpt::maps::CSimplePointsMap scanPoints(const mrpt::obs::CObservation2DRangeScan& scan) {
  mrpt::maps::CSimplePointsMap points;
  points.insertionOptions.minDistBetweenLaserPoints = 0;
  points.insertObservation(scan);
  return points;
}

mrpt::slam::CICP icp2d() {
  mrpt::slam::CICP icp;
  icp.options.thresholdDist = 0.75;
  icp.options.thresholdAng = 0.1;
  icp.options.ALFA = 0.5;
  icp.options.smallestThresholdDist = 0.05;
  icp.options.maxIterations = 200;
  return icp;
}

// Each of 10 real scans, left out of the map of the others, from 3 starts 25 cm and 4 degrees
// off its SLAM pose. MRPT's ICP on its own points map of the same scans is the oracle
// (measured: median 0.9 cm, at most 3.2 cm; the NDT map at 0.2 m: median 1.9 cm, at most
// 7.8 cm, in one corridor start, and 0.56 deg).
TEST(MapApi, Icp2dRecoversKnownOffsetsOfRealLaserScans) {
  const auto frames = malagaKeyframes(12);
  ASSERT_EQ(frames.size(), 12u) << "needs Debian's mrpt-common";
  const double deg = M_PI / 180;
  auto icp = icp2d();
  std::vector<double> errors, oracle_errors;
  double worst_angle = 0;
  for (size_t k = 2; k < frames.size(); ++k) {
    CNDTOccupancyMap ndt(0.2);
    mrpt::maps::CSimplePointsMap points;
    points.insertionOptions.minDistBetweenLaserPoints = 0;
    for (size_t i = 0; i < frames.size(); ++i) {
      if (i == k) continue;
      ASSERT_TRUE(ndt.insertObservation(*frames[i].scan, frames[i].pose));
      points.insertObservation(*frames[i].scan, frames[i].pose);
    }
    const mrpt::maps::CSimplePointsMap scan = scanPoints(*frames[k].scan);
    const CPose2D truth(frames[k].pose);
    for (const CPose2D& offset :
         {CPose2D(0.25, 0, 0), CPose2D(0, -0.25, 4 * deg), CPose2D(-0.15, 0.15, -4 * deg)}) {
      mrpt::slam::CICP::TReturnInfo info, oracle_info;
      const CPose2D ours = icp.Align(&ndt, &scan, truth + offset, info)->getMeanVal();
      const CPose2D oracle = icp.Align(&points, &scan, truth + offset, oracle_info)->getMeanVal();
      const CPose2D error = ours - truth;
      EXPECT_LT(error.norm(), 0.1) << "scan " << k << ", start " << offset;
      EXPECT_LT(std::abs(error.phi()), 1.0 * deg) << "scan " << k << ", start " << offset;
      EXPECT_GT(info.goodness, 0.6);
      errors.push_back(error.norm());
      oracle_errors.push_back((oracle - truth).norm());
      worst_angle = std::max(worst_angle, std::abs(error.phi()));
    }
  }
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  std::cout << "[ icp2d    ] 30 alignments: NDT median " << median(errors) << " m, max "
            << *std::max_element(errors.begin(), errors.end()) << " m, " << worst_angle / deg
            << " deg; points map median " << median(oracle_errors) << " m, max "
            << *std::max_element(oracle_errors.begin(), oracle_errors.end()) << " m\n";
  EXPECT_LT(median(errors), 0.025);
  EXPECT_LT(median(errors), median(oracle_errors) + 0.01);
}

// Two maps of the same scans at their poses; the ratio of one against the other must equal
// the ratio against a points map of the other's occupied means (the same points, another
// path), must be high in place and low when shifted by a few cells.
TEST(MapApi, MatchingRatioAgainstAnotherNdtMap) {
  const auto frames = malagaKeyframes(10);
  ASSERT_EQ(frames.size(), 10u);
  CNDTOccupancyMap a(0.2), b(0.2);
  for (size_t i = 0; i < frames.size(); ++i)
    (i % 2 ? a : b).insertObservation(*frames[i].scan, frames[i].pose);
  mrpt::maps::CSimplePointsMap means;
  b.ndtMap().forEachCell([&](const ndtom::CellView& c) {
    if (!c.stats || c.stats->n == 0 || c.logodds <= 0.f) return;
    const Eigen::Vector3d m = b.ndtMap().geometry().cellCenter(c.index) + c.stats->relative_mean;
    means.insertPoint(float(m.x()), float(m.y()), float(m.z()));
  });
  ASSERT_GT(means.size(), 200u);
  mrpt::maps::TMatchingRatioParams params;
  params.maxMahaDistForCorr = 3;
  const CPose3D same;
  const float ratio = a.compute3DMatchingRatio(&b, same, params);
  EXPECT_NEAR(ratio, a.compute3DMatchingRatio(&means, same, params), 1e-4);
  EXPECT_GT(ratio, 0.3);  // measured 0.37: alternate scans of a moving robot
  EXPECT_LT(a.compute3DMatchingRatio(&b, CPose3D(1.0, -1.0, 0, 0.5, 0, 0), params), 0.5 * ratio);

  // Inside CMultiMetricMaps, as map-partition hands them over.
  mrpt::maps::CMultiMetricMap multi_a, multi_b;
  multi_a.maps.push_back(CNDTOccupancyMap::Create(a));
  multi_b.maps.push_back(CNDTOccupancyMap::Create(b));
  EXPECT_FLOAT_EQ(multi_a.compute3DMatchingRatio(&multi_b, same, params), ratio);
  EXPECT_EQ(a.compute3DMatchingRatio(&multi_b, same, params), ratio);
  CNDTOccupancyMap empty(0.2);
  EXPECT_EQ(a.compute3DMatchingRatio(&empty, same, params), 0.0f);
}

TEST(MapApi, VoxelsAreTheKnownCellsColouredByOccupancy) {
  const auto frames = malagaKeyframes(10);
  ASSERT_EQ(frames.size(), 10u);
  CNDTOccupancyMap map(0.2);
  for (const auto& f : frames) map.insertObservation(*f.scan, f.pose);
  size_t occupied = 0, free = 0;
  std::set<std::tuple<int, int, int>> occupied_cells;
  map.ndtMap().forEachCell([&](const ndtom::CellView& c) {
    if (c.logodds > 0.f) {
      ++occupied;
      occupied_cells.insert({c.index.x, c.index.y, c.index.z});
    }
    free += c.logodds < 0.f;
  });
  auto gl = mrpt::opengl::COctoMapVoxels::Create();
  gl->setVisualizationMode(mrpt::opengl::COctoMapVoxels::COLOR_FROM_OCCUPANCY);
  map.getAsOctoMapVoxels(*gl);
  ASSERT_EQ(gl->getVoxelSetCount(), 2u);
  EXPECT_EQ(gl->getVoxelCount(mrpt::opengl::VOXEL_SET_OCCUPIED), occupied);
  EXPECT_EQ(gl->getVoxelCount(mrpt::opengl::VOXEL_SET_FREESPACE), free);
  const double r = 0.2;
  for (size_t i = 0; i < gl->getVoxelCount(mrpt::opengl::VOXEL_SET_OCCUPIED); ++i) {
    const auto& v = gl->getVoxel(mrpt::opengl::VOXEL_SET_OCCUPIED, i);
    ASSERT_NEAR(v.side_length, r, 1e-12);
    const int x = int(std::floor(v.coords.x / r)), y = int(std::floor(v.coords.y / r)),
              z = int(std::floor(v.coords.z / r));
    ASSERT_TRUE(occupied_cells.count({x, y, z})) << "voxel " << i << " is no occupied cell";
  }
  // Darker is more occupied: every occupied voxel darker than every free one.
  uint8_t darkest_free = 255, brightest_occupied = 0;
  for (size_t i = 0; i < gl->getVoxelCount(mrpt::opengl::VOXEL_SET_FREESPACE); ++i)
    darkest_free = std::min(darkest_free, gl->getVoxel(mrpt::opengl::VOXEL_SET_FREESPACE, i).color.R);
  for (size_t i = 0; i < gl->getVoxelCount(mrpt::opengl::VOXEL_SET_OCCUPIED); ++i)
    brightest_occupied =
        std::max(brightest_occupied, gl->getVoxel(mrpt::opengl::VOXEL_SET_OCCUPIED, i).color.R);
  EXPECT_LT(brightest_occupied, darkest_free);

  map.renderOptions.generate_free_voxels = false;
  map.renderOptions.visible_occupied_voxels = false;
  map.getAsOctoMapVoxels(*gl);
  EXPECT_EQ(gl->getVoxelCount(mrpt::opengl::VOXEL_SET_FREESPACE), 0u);
  EXPECT_EQ(gl->getVoxelCount(mrpt::opengl::VOXEL_SET_OCCUPIED), occupied);
  EXPECT_FALSE(gl->areVoxelsVisible(mrpt::opengl::VOXEL_SET_OCCUPIED));
}

// MRPT's dense 3D grid on the same scans with the same updates (MRPT adds 3 times the
// log-odds of maxOccupancyUpdateCertainty for a hit: logit(0.865) = 3 logit(0.65)): the known
// voxels must be mostly the same set. MRPT steps along a ray in max(|dx|, |dy|, |dz|) equal
// steps, not through every cell it crosses, and keeps 8-bit log-odds, so sets differ at the
// edges.
TEST(MapApi, VoxelsAgreeWithMrptsOccupancyGrid3d) {
  const auto frames = malagaKeyframes(10);
  ASSERT_EQ(frames.size(), 10u);
  CNDTOccupancyMap ndt(0.2);
  ndt.insertionOptions.occupancy.p_hit = 0.865;
  ndt.insertionOptions.occupancy.p_miss = 0.4;
  ndt.insertionOptions.scan.max_range = std::numeric_limits<double>::infinity();  // MRPT: no limit
  for (const auto& f : frames) ndt.insertObservation(*f.scan, f.pose);
  const mrpt::math::TBoundingBox box = ndt.boundingBox();
  mrpt::maps::COccupancyGridMap3D grid(box.min - mrpt::math::TPoint3D(1, 1, 1),
                                       box.max + mrpt::math::TPoint3D(1, 1, 1), 0.2f);
  grid.insertionOptions.maxOccupancyUpdateCertainty = 0.65f;
  grid.insertionOptions.maxFreenessUpdateCertainty = 0.4f;
  for (const auto& f : frames) grid.insertObservation(*f.scan, f.pose);

  auto ours = mrpt::opengl::COctoMapVoxels::Create(), theirs = mrpt::opengl::COctoMapVoxels::Create();
  ndt.getAsOctoMapVoxels(*ours);
  grid.getAsOctoMapVoxels(*theirs);
  using mrpt::opengl::VOXEL_SET_FREESPACE;
  using mrpt::opengl::VOXEL_SET_OCCUPIED;
  const auto keys = [](const mrpt::opengl::COctoMapVoxels& gl, size_t set) {
    std::set<std::tuple<int, int, int>> cells;
    for (size_t i = 0; i < gl.getVoxelCount(set); ++i) {
      const auto& c = gl.getVoxel(set, i).coords;
      cells.insert({int(std::floor(c.x / 0.2 + 1e-3)), int(std::floor(c.y / 0.2 + 1e-3)),
                    int(std::floor(c.z / 0.2 + 1e-3))});
    }
    return cells;
  };
  for (const size_t set : {VOXEL_SET_OCCUPIED, VOXEL_SET_FREESPACE}) {
    const auto a = keys(*ours, set), b = keys(*theirs, set);
    size_t common = 0;
    for (const auto& c : a) common += b.count(c);
    const double jaccard = double(common) / double(a.size() + b.size() - common);
    std::cout << "[ voxels   ] set " << set << ": ours " << a.size() << ", MRPT's "
              << b.size() << ", common " << common << ", Jaccard " << jaccard << "\n";
    EXPECT_GT(a.size(), 100u);
    // Measured 0.92 (occupied) and 0.87 (free).
    EXPECT_GT(jaccard, set == VOXEL_SET_OCCUPIED ? 0.85 : 0.8) << "set " << set;
  }
}

TEST(MapApi, BoundingBoxIsTheTightBoxOfTheKnownCells) {
  const auto frames = malagaKeyframes(5);
  ASSERT_EQ(frames.size(), 5u);
  CNDTOccupancyMap map(0.2);
  const mrpt::math::TBoundingBox empty = map.boundingBox();
  EXPECT_EQ(empty.min, mrpt::math::TPoint3D(0, 0, 0));
  EXPECT_EQ(empty.max, mrpt::math::TPoint3D(0, 0, 0));
  for (const auto& f : frames) map.insertObservation(*f.scan, f.pose);
  const mrpt::math::TBoundingBox box = map.boundingBox();
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  map.ndtMap().forEachCell([&](const ndtom::CellView& c) {
    const Eigen::Vector3d centre = map.ndtMap().geometry().cellCenter(c.index);
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], centre[a] - 0.1);
      hi[a] = std::max(hi[a], centre[a] + 0.1);
    }
  });
  EXPECT_NEAR(box.min.x, lo[0], 1e-9);
  EXPECT_NEAR(box.min.y, lo[1], 1e-9);
  EXPECT_NEAR(box.min.z, lo[2], 1e-9);
  EXPECT_NEAR(box.max.x, hi[0], 1e-9);
  EXPECT_NEAR(box.max.y, hi[1], 1e-9);
  EXPECT_NEAR(box.max.z, hi[2], 1e-9);
  EXPECT_GT(box.max.x - box.min.x, 5.0);
}

TEST(MapApi, SquareDistanceToClosestCorrespondenceIsTheNearestMeanInThePlane) {
  const auto frames = malagaKeyframes(5);
  ASSERT_EQ(frames.size(), 5u);
  CNDTOccupancyMap map(0.2);
  EXPECT_EQ(map.squareDistanceToClosestCorrespondence(0, 0),
            std::numeric_limits<float>::infinity());
  for (const auto& f : frames) map.insertObservation(*f.scan, f.pose);
  std::vector<ndtom::PreparedGaussian> gaussians;
  map.gaussianLookup()->forEachGaussian([&](const auto& g) { gaussians.push_back(g); });
  ASSERT_GT(gaussians.size(), 100u);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-20, 20);
  for (int k = 0; k < 200; ++k) {
    const float x = u(rng), y = u(rng);
    double best = std::numeric_limits<double>::infinity();
    for (const auto& g : gaussians)
      best = std::min(best, std::pow(g.mean.x() - x, 2) + std::pow(g.mean.y() - y, 2));
    EXPECT_NEAR(map.squareDistanceToClosestCorrespondence(x, y), best, 1e-4 * (1 + best));
  }
  // The cached means follow the map.
  map.insertObservation(*frames[0].scan, frames[0].pose + CPose3D(30, 30, 0, 0, 0, 0));
  EXPECT_LT(map.squareDistanceToClosestCorrespondence(float(frames[0].pose.x() + 30),
                                                      float(frames[0].pose.y() + 30)),
            100.0f);
}

TEST(MapApi, PointOccupancyAndCastRayFollowTheCore) {
  const auto frames = malagaKeyframes(5);
  ASSERT_EQ(frames.size(), 5u);
  CNDTOccupancyMap map(0.2);
  for (const auto& f : frames) map.insertObservation(*f.scan, f.pose);
  size_t hits = 0;
  map.ndtMap().forEachCell([&](const ndtom::CellView& c) {
    const Eigen::Vector3d centre = map.ndtMap().geometry().cellCenter(c.index);
    double p = -1;
    ASSERT_TRUE(map.getPointOccupancy(float(centre.x()), float(centre.y()), float(centre.z()), p));
    EXPECT_NEAR(p, 1.0 / (1.0 + std::exp(-double(c.logodds))), 1e-6);
  });
  double p = -1;
  EXPECT_FALSE(map.getPointOccupancy(1e4f, 1e4f, 0, p));

  // Rays from the first robot pose in the scan plane: the first occupied cell, as the core
  // finds it, and never through an unknown cell unless asked to.
  const CPose3D sensor = frames[0].pose + frames[0].scan->sensorPose;
  const mrpt::math::TPoint3D origin(sensor.x(), sensor.y(), sensor.z());
  for (int k = 0; k < 72; ++k) {
    const double a = k * 5 * M_PI / 180;
    const mrpt::math::TPoint3D direction(std::cos(a), std::sin(a), 0);
    mrpt::math::TPoint3D end;
    const bool hit = map.castRay(origin, direction, end, true, 30.0);
    const auto core = ndtom::castRay(map.ndtMap(), {origin.x, origin.y, origin.z},
                                     {direction.x, direction.y, direction.z}, 30.0);
    ASSERT_EQ(hit, core.has_value());
    if (!hit) continue;
    ++hits;
    const Eigen::Vector3d centre = map.ndtMap().geometry().cellCenter(core->cell);
    EXPECT_NEAR(end.x, centre.x(), 1e-9);
    EXPECT_EQ(map.cellState(end), ndtom::CellState::Occupied);
    mrpt::math::TPoint3D careful_end;
    if (map.castRay(origin, direction, careful_end, false, 30.0)) {
      EXPECT_EQ(careful_end, end) << "a hit through known cells is the same hit";
    }
  }
  EXPECT_GT(hits, 30u);  // the 180-degree scanner saw walls in most directions ahead
  EXPECT_THROW(map.castRay(origin, {0, 0, 0}, *std::make_unique<mrpt::math::TPoint3D>()),
               std::exception);
}

}  // namespace
