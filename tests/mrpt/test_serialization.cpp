// Serialization and copies: a map written to an MRPT archive and read back, copied, or
// carried inside a CMultiMetricMap (as rbpf-slam's particles are) is bit-for-bit the same.
#include <gtest/gtest.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/serialization/CArchive.h>

#include <random>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom/map_io.h"

using Eigen::Vector3d;
using mrpt_ndtom::CNDTOccupancyMap;

namespace {

std::vector<Vector3d> randomScan(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-4, 4);
  std::vector<Vector3d> points;
  for (int i = 0; i < 3000; ++i) {
    const double a = u(rng), b = u(rng);
    points.emplace_back(i % 2 ? Vector3d(a, b, -1 + 0.01 * u(rng)) : Vector3d(5, a, b));
  }
  return points;
}

CNDTOccupancyMap::Ptr sampleMap() {
  auto map = CNDTOccupancyMap::Create(0.3);
  map->insertionOptions.p_hit = 0.65;
  map->likelihoodOptions.decimation = 3;
  map->renderOptions.subdivisions = 2;
  map->genericMapParams.enableSaveAs3DObject = false;
  for (unsigned s = 0; s < 3; ++s) map->insertPoints(randomScan(s), Vector3d(0.1 * s, 0, 0.5));
  return map;
}

// Every cell identical: log-odds, count and the exact bits of mean and scatter.
void expectSameMaps(const CNDTOccupancyMap& a, const CNDTOccupancyMap& b) {
  EXPECT_EQ(ndtom::encodeMap(a.ndtMap()), ndtom::encodeMap(b.ndtMap()));
  EXPECT_EQ(a.ndtMap().numCells(), b.ndtMap().numCells());
  a.ndtMap().forEachCell([&](const ndtom::CellView& c) {
    const auto other = b.ndtMap().cell(c.index);
    ASSERT_TRUE(other.has_value());
    EXPECT_EQ(other->logodds, c.logodds);
    ASSERT_EQ(other->stats == nullptr, c.stats == nullptr);
    if (!c.stats) return;
    EXPECT_EQ(other->stats->n, c.stats->n);
    EXPECT_EQ(other->stats->mean, c.stats->mean);
    EXPECT_EQ(other->stats->scatter, c.stats->scatter);
  });
  EXPECT_TRUE(a.insertionOptions == b.insertionOptions);
  EXPECT_TRUE(a.likelihoodOptions == b.likelihoodOptions);
  EXPECT_TRUE(a.renderOptions == b.renderOptions);
  EXPECT_EQ(a.genericMapParams.enableSaveAs3DObject, b.genericMapParams.enableSaveAs3DObject);
}

template <class T>
std::shared_ptr<T> roundTrip(const T& object) {
  mrpt::io::CMemoryStream buffer;
  mrpt::serialization::archiveFrom(buffer) << object;
  buffer.Seek(0);
  const auto read = mrpt::serialization::archiveFrom(buffer).ReadObject();
  return std::dynamic_pointer_cast<T>(read);
}

}  // namespace

TEST(Serialization, ArchiveRoundTripIsExact) {
  const auto map = sampleMap();
  ASSERT_GT(map->ndtMap().numGaussians(), 50u);
  const auto copy = roundTrip(*map);
  ASSERT_TRUE(copy);
  expectSameMaps(*map, *copy);
  // And it still works: same likelihood-relevant content, can take more data.
  copy->insertPoints(randomScan(9), Vector3d::Zero());
  EXPECT_GT(copy->ndtMap().numCells(), 0u);
}

TEST(Serialization, EmptyMapRoundTrip) {
  CNDTOccupancyMap empty(0.7);
  const auto copy = roundTrip(empty);
  ASSERT_TRUE(copy);
  EXPECT_TRUE(copy->isEmpty());
  EXPECT_EQ(copy->ndtMap().options().resolution, 0.7);
}

TEST(Serialization, CopyConstructionAndAssignment) {
  const auto map = sampleMap();
  map->gaussianLookup();  // a built lookup is shared, not rebuilt
  CNDTOccupancyMap copy(*map);
  expectSameMaps(*map, copy);
  EXPECT_EQ(copy.gaussianLookup(), map->gaussianLookup());
  CNDTOccupancyMap assigned(1.0);
  assigned = *map;
  expectSameMaps(*map, assigned);
  // Independent afterwards.
  copy.insertPoints(randomScan(11), Vector3d::Zero());
  EXPECT_NE(ndtom::encodeMap(copy.ndtMap()), ndtom::encodeMap(map->ndtMap()));
  EXPECT_NE(copy.gaussianLookup(), map->gaussianLookup());
}

TEST(Serialization, InsideAMultiMetricMap) {
  mrpt::maps::TSetOfMetricMapInitializers inits;
  CNDTOccupancyMap::TMapDefinition def;
  def.insertionOpts.resolution = 0.4;
  inits.push_back(def);
  mrpt::maps::CMultiMetricMap multi(inits);
  ASSERT_EQ(multi.countMapsByClass<CNDTOccupancyMap>(), 1u);
  multi.mapByClass<CNDTOccupancyMap>()->insertPoints(randomScan(4), Vector3d(0, 0, 0.3));

  const auto serialized = roundTrip(multi);  // what rbpf-slam does to duplicate particles
  ASSERT_TRUE(serialized);
  ASSERT_EQ(serialized->countMapsByClass<CNDTOccupancyMap>(), 1u);
  expectSameMaps(*multi.mapByClass<CNDTOccupancyMap>(),
                 *serialized->mapByClass<CNDTOccupancyMap>());

  mrpt::maps::CMultiMetricMap copied(multi);
  ASSERT_EQ(copied.countMapsByClass<CNDTOccupancyMap>(), 1u);
  expectSameMaps(*multi.mapByClass<CNDTOccupancyMap>(), *copied.mapByClass<CNDTOccupancyMap>());
}

TEST(Serialization, UnknownVersionAndDamagedDataThrow) {
  const auto map = sampleMap();
  mrpt::io::CMemoryStream buffer;
  mrpt::serialization::archiveFrom(buffer) << *map;
  std::vector<uint8_t> bytes(buffer.getTotalBytesCount());
  std::memcpy(bytes.data(), buffer.getRawBufferData(), bytes.size());

  // The version byte follows the class name in MRPT's object header.
  const std::string name = "mrpt_ndtom::CNDTOccupancyMap";
  const auto at = std::search(bytes.begin(), bytes.end(), name.begin(), name.end());
  ASSERT_NE(at, bytes.end());
  const size_t version_at = size_t(at - bytes.begin()) + name.size();
  ASSERT_EQ(bytes[version_at], 0) << "the current version is 0";

  auto readBack = [](std::vector<uint8_t> data) {
    mrpt::io::CMemoryStream in;
    in.assignMemoryNotOwn(data.data(), data.size());
    mrpt::serialization::archiveFrom(in).ReadObject();
  };
  auto wrong_version = bytes;
  wrong_version[version_at] = 9;
  EXPECT_THROW(readBack(wrong_version), std::exception);

  auto damaged = bytes;  // flip a byte inside the map data: the core's checksum catches it
  damaged[damaged.size() - 40] ^= 0x5A;
  EXPECT_THROW(readBack(damaged), std::exception);

  auto truncated = bytes;
  truncated.resize(bytes.size() / 2);
  EXPECT_THROW(readBack(truncated), std::exception);
}

TEST(Serialization, CoarsenedCopyIsTheCoresMultiResolutionMap) {
  const auto map = sampleMap();
  const auto coarse = map->getCoarsened(3);
  ASSERT_TRUE(coarse);
  EXPECT_EQ(ndtom::encodeMap(coarse->ndtMap()), ndtom::encodeMap(map->ndtMap().coarsened(3)));
  EXPECT_DOUBLE_EQ(coarse->insertionOptions.resolution, 0.9);
  EXPECT_EQ(coarse->insertionOptions.p_hit, map->insertionOptions.p_hit);
  EXPECT_TRUE(coarse->likelihoodOptions == map->likelihoodOptions);
  EXPECT_TRUE(coarse->renderOptions == map->renderOptions);
  EXPECT_LT(coarse->ndtMap().numCells(), map->ndtMap().numCells());
  // Points are conserved by the exact merge.
  uint64_t fine_points = 0, coarse_points = 0;
  map->ndtMap().forEachCell(
      [&](const ndtom::CellView& c) { fine_points += c.stats ? c.stats->n : 0; });
  coarse->ndtMap().forEachCell(
      [&](const ndtom::CellView& c) { coarse_points += c.stats ? c.stats->n : 0; });
  EXPECT_EQ(coarse_points, fine_points);
  // It is a working map: more data can go in at the coarse resolution.
  coarse->insertPoints(randomScan(21), Vector3d::Zero());
  EXPECT_THROW(map->getCoarsened(0), std::exception);
}
