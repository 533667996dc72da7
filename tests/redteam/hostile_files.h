// Writers of the red team's inputs: files in the formats ndtom-map and the loaders read,
// valid or damaged on purpose.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace redteam {

void writeFile(const std::string& path, const std::string& bytes);
void writeFile(const std::string& path, const std::vector<uint8_t>& bytes);
std::string readFile(const std::string& path);

/// A PCD header for fields x y z (float) and `points` points, `data` ascii/binary/...
std::string pcdHeader(uint64_t points, const std::string& data);
/// x y z float32 records.
std::string pcdBinaryPoints(const std::vector<Eigen::Vector3d>& points);

/// A 16-bit grey PNG of `width` x `height` pixels all `value`, compressed row by row (a few
/// kB for millions of pixels, without holding them).
void writeFlatPng(const std::string& path, uint32_t width, uint32_t height, uint16_t value);

/// `n` points `range` metres from `centre`, in random directions.
std::vector<Eigen::Vector3d> pointsAround(const Eigen::Vector3d& centre, double range, int n,
                                          unsigned seed);

/// KITTI lines (identity rotation) for sensor positions.
std::string kittiPoses(const std::vector<Eigen::Vector3d>& positions);

/// An MRPT rawlog (observations format): per scan an odometry reading at `x` = scan index
/// and a 2D laser scan of 361 rays of `range` metres (CObservation2DRangeScan).
void writeLaserRawlog(const std::string& path, int scans, float range);

/// A CNDTOccupancyMap of a few real-like cells, serialized as ndtom-map writes .ndtommap;
/// `map_size_at` receives the offset of the u64 size of the map data.
std::vector<uint8_t> ndtommapBytes(size_t* map_size_at);

}  // namespace redteam
