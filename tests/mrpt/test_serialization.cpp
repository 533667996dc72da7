// Serialization and copies: a map written to an MRPT archive and read back, copied, or
// carried inside a CMultiMetricMap (as rbpf-slam's particles are) is bit-for-bit the same.
// Archives of earlier versions still load (insertion options without threads, likelihood
// options without the method).
#include <gtest/gtest.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/serialization/CArchive.h>

#include <fstream>
#include <iterator>
#include <random>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "mrpt_ndtom/encoded_archive.h"
#include "ndtom/files/map_io.h"

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
  map->insertionOptions.occupancy.p_hit = 0.65;
  map->insertionOptions.scan.threads = 3;
  map->likelihoodOptions.decimation = 3;
  map->likelihoodOptions.likelihood_method = CNDTOccupancyMap::TLikelihoodMethod::NdtMcl;
  map->likelihoodOptions.ndt_mcl_scan_factor = 4;
  map->likelihoodOptions.ndt_mcl_map_factor = 2;
  map->likelihoodOptions.ndt_mcl_max_gaussians = 250;
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
    EXPECT_EQ(other->stats->relative_mean, c.stats->relative_mean);
    EXPECT_EQ(other->stats->scatter, c.stats->scatter);
  });
  EXPECT_TRUE(a.insertionOptions == b.insertionOptions);
  EXPECT_TRUE(a.likelihoodOptions == b.likelihoodOptions);
  EXPECT_TRUE(a.renderOptions == b.renderOptions);
  EXPECT_EQ(a.genericMapParams.enableSaveAs3DObject, b.genericMapParams.enableSaveAs3DObject);
}

// Insertion options version 1 is version 0 with `threads` (int32) appended.
constexpr size_t kThreadsInInsertionOptions = 86;
constexpr size_t kInsertionOptionsV1 = kThreadsInInsertionOptions + 4;
// Likelihood options version 1 is version 0 with the method and the three NdtMcl options (four
// int32) appended.
constexpr size_t kMethodInLikelihoodOptions = 42;
constexpr size_t kLikelihoodOptionsV1 = kMethodInLikelihoodOptions + 16;
// Render options version 1 is version 0 with the four voxel-set flags appended.
constexpr size_t kVoxelFlagsInRenderOptions = 54;

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
  EXPECT_EQ(copy->insertionOptions.scan.threads, 3);
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
  map->gaussianLookup();  // built lookups are shared, not rebuilt
  map->ndtMclMap();
  CNDTOccupancyMap copy(*map);
  expectSameMaps(*map, copy);
  EXPECT_EQ(copy.gaussianLookup(), map->gaussianLookup());
  EXPECT_EQ(copy.ndtMclMap(), map->ndtMclMap());
  CNDTOccupancyMap assigned(1.0);
  assigned = *map;
  expectSameMaps(*map, assigned);
  // Independent afterwards.
  copy.insertPoints(randomScan(11), Vector3d::Zero());
  EXPECT_NE(ndtom::encodeMap(copy.ndtMap()), ndtom::encodeMap(map->ndtMap()));
  EXPECT_NE(copy.gaussianLookup(), map->gaussianLookup());
  EXPECT_NE(copy.ndtMclMap(), map->ndtMclMap());
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
  ASSERT_EQ(bytes[version_at], 1) << "the current version is 1";

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

namespace {

std::vector<uint8_t> archiveBytes(const mrpt::serialization::CSerializable& object) {
  mrpt::io::CMemoryStream buffer;
  mrpt::serialization::archiveFrom(buffer) << object;
  const auto* raw = static_cast<const uint8_t*>(buffer.getRawBufferData());
  return {raw, raw + buffer.getTotalBytesCount()};
}

template <class Options>
std::vector<uint8_t> optionBytes(const Options& options) {
  mrpt::io::CMemoryStream buffer;
  auto archive = mrpt::serialization::archiveFrom(buffer);
  options.writeToStream(archive);
  const auto* raw = static_cast<const uint8_t*>(buffer.getRawBufferData());
  return {raw, raw + buffer.getTotalBytesCount()};
}

size_t offsetOf(const std::vector<uint8_t>& haystack, const std::vector<uint8_t>& needle) {
  const auto at = std::search(haystack.begin(), haystack.end(), needle.begin(), needle.end());
  EXPECT_NE(at, haystack.end());
  return size_t(at - haystack.begin());
}

testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return testing::AssertionSuccess();
  return testing::AssertionFailure() << "\"" << part << "\" not in: " << text.substr(0, 400);
}

// Reads `bytes` into `map`; returns the exception's message ("" if none was thrown).
std::string readInto(CNDTOccupancyMap& map, const std::vector<uint8_t>& bytes) {
  mrpt::io::CMemoryStream in;
  in.assignMemoryNotOwn(bytes.data(), bytes.size());
  try {
    mrpt::serialization::archiveFrom(in).ReadObject(&map);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// An archive of sampleMap() and where its parts are, to damage them one by one.
struct Archive {
  CNDTOccupancyMap::Ptr map = sampleMap();
  std::vector<uint8_t> bytes = archiveBytes(*map);
  size_t insertion = offsetOf(bytes, optionBytes(map->insertionOptions));
  size_t likelihood = offsetOf(bytes, optionBytes(map->likelihoodOptions));
  size_t render = offsetOf(bytes, optionBytes(map->renderOptions));
  size_t map_data = offsetOf(bytes, ndtom::encodeMap(map->ndtMap()));
  size_t map_size = map_data - 8;  // uint64 byte count

  template <class T>
  std::string readWith(size_t at, T value) const {
    auto damaged = bytes;
    std::memcpy(damaged.data() + at, &value, sizeof(value));
    CNDTOccupancyMap read;
    return readInto(read, damaged);
  }
};

}  // namespace

TEST(Serialization, CorruptSizeFieldFailsAtTheEndOfTheData) {
  const Archive a;
  ASSERT_EQ(a.readWith(a.map_size, uint64_t(a.bytes.size() - a.map_data - 1)), "")
      << "sanity: the size field is where expected";
  // Sizes beyond the memory budget are refused before reading; others are read in chunks and
  // fail when the data runs out, never in one huge allocation (which ASan would report).
  for (const uint64_t size : {~uint64_t(0), uint64_t(1) << 62, uint64_t(1) << 40})
    EXPECT_TRUE(contains(a.readWith(a.map_size, size), "over the memory budget")) << size;
  EXPECT_TRUE(contains(a.readWith(a.map_size, uint64_t(a.bytes.size())),
                       "the archive ends inside the map data"));
  EXPECT_TRUE(contains(a.readWith(a.map_size, uint64_t(3)), "MRPT archive"));
}

TEST(Serialization, CorruptOptionsAreRejectedByName) {
  const Archive a;
  // Offsets inside each option block: a version byte, then the fields in writeToStream order.
  EXPECT_TRUE(contains(a.readWith(a.insertion + 1, -0.2), "resolution"));
  EXPECT_TRUE(contains(a.readWith(a.insertion + 9, uint8_t(7)),
                       "insertionOptions.occupancy_enabled: stored bool is 7"));
  EXPECT_TRUE(contains(a.readWith(a.insertion + 10, 4e4), "p_hit"));
  EXPECT_TRUE(contains(a.readWith(a.insertion + 58, int32_t(5)), "insertionOptions.ray_mode = 5"));
  EXPECT_TRUE(contains(a.readWith(a.insertion + 62, uint32_t(0)), "decimation"));
  EXPECT_TRUE(contains(a.readWith(a.insertion + 86, int32_t(0)), "insertionOptions: threads = 0"));
  EXPECT_TRUE(
      contains(a.readWith(a.insertion + 86, int32_t(-4)), "insertionOptions: threads = -4"));
  EXPECT_TRUE(
      contains(a.readWith(a.insertion + 86, int32_t(1000)), "insertionOptions: threads = 1000"));
  EXPECT_TRUE(contains(a.readWith(a.insertion, uint8_t(2)), "unknown serialization version"));
  EXPECT_TRUE(contains(a.readWith(a.likelihood + 1, uint32_t(0)), "likelihoodOptions: decimation"));
  EXPECT_TRUE(contains(a.readWith(a.likelihood + 17, uint8_t(2)),
                       "likelihoodOptions.search_neighbours: stored bool is 2"));
  EXPECT_TRUE(contains(a.readWith(a.likelihood + kMethodInLikelihoodOptions, int32_t(2)),
                       "likelihoodOptions.likelihood_method = 2: unknown method"));
  EXPECT_TRUE(contains(a.readWith(a.likelihood + kMethodInLikelihoodOptions + 4, int32_t(0)),
                       "likelihoodOptions: ndt_mcl_scan_factor = 0"));
  EXPECT_TRUE(contains(a.readWith(a.likelihood + kMethodInLikelihoodOptions + 8, int32_t(99)),
                       "likelihoodOptions: ndt_mcl_map_factor = 99"));
  EXPECT_TRUE(contains(a.readWith(a.likelihood + kMethodInLikelihoodOptions + 12, int32_t(-3)),
                       "likelihoodOptions: ndt_mcl_max_gaussians = -3"));
  EXPECT_TRUE(contains(a.readWith(a.likelihood, uint8_t(2)), "unknown serialization version"));
  EXPECT_TRUE(contains(a.readWith(a.render + 9, uint32_t(30)), "renderOptions: subdivisions = 30"));
  EXPECT_TRUE(contains(a.readWith(a.render + 41, int32_t(99)), "renderOptions.colormap = 99"));
  EXPECT_TRUE(contains(a.readWith(a.render + 45, uint8_t(0xff)),
                       "renderOptions.show_free_cells: stored bool is 255"));
  // genericMapParams is MRPT's own object: name, version byte, then its three bools.
  const std::string generic = "mrpt::maps::TMapGenericParams";
  const size_t generic_at = offsetOf(a.bytes, {generic.begin(), generic.end()}) + generic.size();
  EXPECT_TRUE(contains(a.readWith(generic_at + 2, uint8_t(5)),
                       "genericMapParams.enableObservationLikelihood: stored bool is 5"));
}

TEST(Serialization, FailedReadLeavesTheMapUnchanged) {
  const Archive a;
  auto damaged = a.bytes;
  damaged[a.map_data + 60] ^= 0x10;  // the core's checksum fails, after all options were read
  CNDTOccupancyMap map(0.4);
  map.insertionOptions.occupancy.p_hit = 0.7;
  map.renderOptions.quantiles = 2.0;
  map.insertPoints(randomScan(5), Vector3d::Zero());
  const auto before = archiveBytes(map);
  EXPECT_TRUE(contains(readInto(map, damaged), "checksum"));
  EXPECT_EQ(archiveBytes(map), before);
  // Damage in another part, and truncated archives.
  EXPECT_NE(a.readWith(a.render + 41, int32_t(-7)), "");
  // Every length through the options, then 200 lengths through the map data.
  for (size_t length = 0; length < a.bytes.size();
       length += length < a.map_data ? 1 : a.bytes.size() / 200 + 1) {
    const std::vector<uint8_t> cut(a.bytes.begin(), a.bytes.begin() + long(length));
    ASSERT_NE(readInto(map, cut), "") << length;
    ASSERT_EQ(archiveBytes(map), before) << length;
  }
  EXPECT_EQ(readInto(map, a.bytes), "");
  expectSameMaps(*a.map, map);
}

TEST(Serialization, CoarsenedCopyIsTheCoresMultiResolutionMap) {
  const auto map = sampleMap();
  const auto coarse = map->getCoarsened(3);
  ASSERT_TRUE(coarse);
  EXPECT_EQ(ndtom::encodeMap(coarse->ndtMap()), ndtom::encodeMap(map->ndtMap().coarsened(3)));
  EXPECT_DOUBLE_EQ(coarse->insertionOptions.resolution, 0.9);
  EXPECT_EQ(coarse->insertionOptions.occupancy.p_hit, map->insertionOptions.occupancy.p_hit);
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

namespace {

std::vector<uint8_t> fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST(Serialization, ArchiveOfThePreviousVersionLoadsWithOneThread) {
  // Written by the plugin before `threads` existed (see tests/data/mrpt-archives/README.md).
  const std::vector<uint8_t> old =
      fileBytes(std::string(NDTOM_TEST_DATA_DIR) + "/mrpt-archives/insertion_options_v0.archive");
  ASSERT_EQ(old.size(), 7045u);
  // MRPT's header (0x80 | name length, the name), the map's version, then the options' version.
  const std::string name = "mrpt_ndtom::CNDTOccupancyMap";
  const size_t insertion = 1 + name.size() + 1;
  ASSERT_EQ(old[insertion - 1], 0) << "map version";
  ASSERT_EQ(old[insertion], 0) << "insertion options version";

  CNDTOccupancyMap map(0.5);
  map.insertionOptions.scan.threads = 4;
  ASSERT_EQ(readInto(map, old), "");
  const auto& o = map.insertionOptions;
  EXPECT_EQ(o.scan.threads, 1);
  EXPECT_EQ(o.resolution, 1.0);
  EXPECT_TRUE(o.occupancy.enabled);
  EXPECT_EQ(o.occupancy.p_hit, 0.65);
  EXPECT_EQ(o.occupancy.p_miss, 0.45);
  EXPECT_EQ(o.occupancy.logodds_min, -2.5);
  EXPECT_EQ(o.occupancy.logodds_max, 3.0);
  EXPECT_EQ(o.scan.min_range, 0.6);
  EXPECT_EQ(o.scan.max_range, 8.0);
  EXPECT_EQ(o.scan.ray_mode, ndtom::RayMode::PerHitCell);
  EXPECT_EQ(o.decimation, 2u);
  EXPECT_EQ(o.decimation_3d_range, 3u);
  EXPECT_EQ(o.regularization.min_eigen_ratio, 0.02);
  EXPECT_EQ(o.regularization.min_eigen_abs, 2e-6);
  EXPECT_EQ(map.likelihoodOptions.decimation, 4u);
  EXPECT_EQ(map.likelihoodOptions.scale, 0.5);
  EXPECT_EQ(map.likelihoodOptions.likelihood_method, CNDTOccupancyMap::TLikelihoodMethod::Points);
  EXPECT_EQ(map.likelihoodOptions.ndt_mcl_scan_factor, 2);
  EXPECT_EQ(map.likelihoodOptions.ndt_mcl_map_factor, 1);
  EXPECT_EQ(map.likelihoodOptions.ndt_mcl_max_gaussians, 300);
  EXPECT_TRUE(map.renderOptions.show_free_cells);
  EXPECT_EQ(map.ndtMap().numCells(), 97u);
  EXPECT_EQ(map.ndtMap().numGaussians(), 46u);
  // The stored map, in file format version 1, then MRPT's one-byte end flag.
  const std::string magic = "NDTOMMAP";
  const size_t map_at = offsetOf(old, std::vector<uint8_t>(magic.begin(), magic.end()));
  ASSERT_EQ(old[map_at + 8], 1) << "file format version";
  const std::vector<uint8_t> old_map_data(old.begin() + long(map_at), old.end() - 1);
  EXPECT_EQ(ndtom::encodeMap(ndtom::decodeMap(old_map_data.data(), old_map_data.size())),
            ndtom::encodeMap(map.ndtMap()));

  // Written again the map is version 1 and holds the current file format; the three option
  // blocks are version 1, and otherwise the same bytes.
  std::vector<uint8_t> again = archiveBytes(map);
  const std::vector<uint8_t> map_data = ndtom::encodeMap(map.ndtMap());
  ASSERT_EQ(offsetOf(again, map_data) + map_data.size() + 1, again.size());
  EXPECT_EQ(again[insertion - 1], 1) << "map version";
  again.erase(again.end() - 1 - long(map_data.size()), again.end() - 1);
  again.insert(again.end() - 1, old_map_data.begin(), old_map_data.end());
  uint64_t size = old_map_data.size();  // the size field before the map data
  std::memcpy(&again[again.size() - 1 - old_map_data.size() - 8], &size, 8);
  again[insertion - 1] = 0;
  ASSERT_EQ(again.size(), old.size() + 4 + 16 + 4);
  const size_t likelihood = insertion + kInsertionOptionsV1;
  const size_t render = likelihood + kLikelihoodOptionsV1;
  EXPECT_EQ(again[insertion], 1);
  EXPECT_EQ(again[likelihood], 1);
  EXPECT_EQ(again[render], 1);
  again[render] = 0;
  again.erase(again.begin() + long(render + kVoxelFlagsInRenderOptions),
              again.begin() + long(render + kVoxelFlagsInRenderOptions + 4));
  again[likelihood] = 0;
  again.erase(again.begin() + long(likelihood + kMethodInLikelihoodOptions),
              again.begin() + long(likelihood + kMethodInLikelihoodOptions + 16));
  again[insertion] = 0;
  again.erase(again.begin() + long(insertion + kThreadsInInsertionOptions),
              again.begin() + long(insertion + kThreadsInInsertionOptions + 4));
  EXPECT_TRUE(again == old);
}

TEST(Serialization, HandMadeLikelihoodVersion0ArchiveLoadsWithThePointsMethod) {
  // sampleMap() (NdtMcl, factors 4 and 2, 250 Gaussians) in the likelihood options' version
  // 0 layout: version byte 0, none of the four fields version 1 added.
  const Archive a;
  ASSERT_EQ(a.bytes[a.likelihood], 1);
  std::vector<uint8_t> v0 = a.bytes;
  v0[a.likelihood] = 0;
  v0.erase(v0.begin() + long(a.likelihood + kMethodInLikelihoodOptions),
           v0.begin() + long(a.likelihood + kMethodInLikelihoodOptions + 16));
  CNDTOccupancyMap map;
  ASSERT_EQ(readInto(map, v0), "");
  const auto& o = map.likelihoodOptions;
  EXPECT_EQ(o.likelihood_method, CNDTOccupancyMap::TLikelihoodMethod::Points);
  EXPECT_EQ(o.ndt_mcl_scan_factor, 2);
  EXPECT_EQ(o.ndt_mcl_map_factor, 1);
  EXPECT_EQ(o.ndt_mcl_max_gaussians, 300);
  EXPECT_EQ(o.decimation, 3u) << "the version 0 fields as stored";
  map.likelihoodOptions = a.map->likelihoodOptions;
  expectSameMaps(*a.map, map);
}

TEST(Serialization, HandMadeVersion0ArchiveLoadsWithOneThread) {
  // sampleMap() (threads = 3) in the version 0 layout: version byte 0, no threads field.
  const Archive a;
  ASSERT_EQ(a.bytes[a.insertion], 1);
  std::vector<uint8_t> v0 = a.bytes;
  v0[a.insertion] = 0;
  v0.erase(v0.begin() + long(a.insertion + kThreadsInInsertionOptions),
           v0.begin() + long(a.insertion + kThreadsInInsertionOptions + 4));
  CNDTOccupancyMap map;
  ASSERT_EQ(readInto(map, v0), "");
  EXPECT_EQ(map.insertionOptions.scan.threads, 1);
  map.insertionOptions.scan.threads = 3;
  expectSameMaps(*a.map, map);
}

TEST(Serialization, ArchiveWhoseOptionsDisagreeWithItsMapIsRefused) {
  // The insertion options block: version byte, resolution (double), occupancy flag (byte),
  // p_hit (double). sampleMap() is 0.3 m with p_hit 0.65; its map data says the same.
  const Archive a;
  const size_t resolution = a.insertion + 1, p_hit = a.insertion + 1 + 8 + 1;
  double stored = 0;
  std::memcpy(&stored, a.bytes.data() + p_hit, 8);
  ASSERT_EQ(stored, 0.65);
  const std::string by_p_hit = a.readWith(p_hit, 0.7);
  EXPECT_NE(by_p_hit.find("p_hit (0.69999999999999996 vs 0.65000000000000002)"), std::string::npos)
      << by_p_hit;
  const std::string by_resolution = a.readWith(resolution, 0.25);
  EXPECT_NE(by_resolution.find("resolution (0.25 vs 0.29999999999999999)"), std::string::npos)
      << by_resolution;
  // The map read into is left as it was.
  const auto before = sampleMap();
  auto target = sampleMap();
  auto damaged = a.bytes;
  const double other = 0.7;
  std::memcpy(damaged.data() + p_hit, &other, 8);
  EXPECT_NE(readInto(*target, damaged), "");
  expectSameMaps(*before, *target);
}

TEST(Serialization, OptionsChangedSinceTheLastInsertionApplyToTheWrittenMap) {
  const auto map = sampleMap();
  map->insertionOptions.occupancy.p_miss = 0.45;
  map->insertionOptions.occupancy.logodds_min = -1.0;
  const auto copy = roundTrip(*map);
  ASSERT_TRUE(copy);
  EXPECT_EQ(copy->insertionOptions.occupancy.p_miss, 0.45);
  // As the next insertion would: the same cells merged into a map with the new bounds.
  ndtom::NdtMap expected(map->insertionOptions.toMapOptions());
  expected.merge(map->ndtMap());
  EXPECT_EQ(ndtom::encodeMap(copy->ndtMap()), ndtom::encodeMap(expected));
  float lowest = 0;
  copy->ndtMap().forEachCell([&](const ndtom::CellView& c) { lowest = std::min(lowest, c.logodds); });
  EXPECT_GE(lowest, -1.0f);
  EXPECT_EQ(copy->ndtMap().options().occupancy.p_miss, 0.45);

  // A new resolution cannot apply to a map with data: writing says so.
  map->insertionOptions.resolution = 0.5;
  mrpt::io::CMemoryStream buffer;
  try {
    mrpt::serialization::archiveFrom(buffer) << *map;
    ADD_FAILURE() << "a pending resolution change was written";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("resolution cannot change"), std::string::npos)
        << e.what();
  }
}

// ndtom-map encodes its map once for the .ndtom and the .ndtommap: the archive written with
// the encoding at hand is the archive `<<` writes, and options changed since the last
// insertion still apply (the given encoding is then not the archive's).
TEST(Serialization, ArchiveWithTheEncodingAtHandIsTheSame) {
  const auto archived = [](const CNDTOccupancyMap& map, const std::vector<uint8_t>* encoded) {
    mrpt::io::CMemoryStream buffer;
    auto archive = mrpt::serialization::archiveFrom(buffer);
    if (encoded)
      mrpt_ndtom::writeWithEncodedMap(archive, map, *encoded);
    else
      archive << map;
    const auto* data = static_cast<const uint8_t*>(buffer.getRawBufferData());
    return std::vector<uint8_t>(data, data + buffer.getTotalBytesCount());
  };
  const auto map = sampleMap();
  const std::vector<uint8_t> encoded = ndtom::encodeMap(map->ndtMap());
  EXPECT_EQ(archived(*map, &encoded), archived(*map, nullptr));
  // Only that map takes the given bytes, and only within the call.
  const auto other = sampleMap();
  other->insertPoints(randomScan(7), Vector3d::Zero());
  const std::vector<uint8_t> other_encoded = ndtom::encodeMap(other->ndtMap());
  EXPECT_EQ(archived(*other, &other_encoded), archived(*other, nullptr));
  EXPECT_NE(archived(*other, nullptr), archived(*map, nullptr));

  map->insertionOptions.occupancy.p_miss = 0.45;  // pending: the map is written under it
  const auto written = archived(*map, &encoded);
  EXPECT_EQ(written, archived(*map, nullptr));
  mrpt::io::CMemoryStream buffer;
  buffer.assignMemoryNotOwn(written.data(), written.size());
  const auto copy = std::dynamic_pointer_cast<CNDTOccupancyMap>(
      mrpt::serialization::archiveFrom(buffer).ReadObject());
  ASSERT_TRUE(copy);
  EXPECT_EQ(copy->ndtMap().options().occupancy.p_miss, 0.45);
}
