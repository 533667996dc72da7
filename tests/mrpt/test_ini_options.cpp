// CNDTOccupancyMap from .ini text through MRPT's own machinery (TSetOfMetricMapInitializers,
// CMultiMetricMap): the options read back equal the text, survive save -> load, and bad
// values fail at load time with the option's name.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <sstream>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "support/thrown_message.h"

using mrpt_ndtom::CNDTOccupancyMap;
using ndtom::testing::thrownMessage;

namespace {

const char* kIni = R"ini(
[MetricMap]
ndtOccupancyMap_count = 1
pointsMap_count       = 1

[MetricMap_ndtOccupancyMap_00_creationOpts]
enableSaveAs3DObject        = false
enableObservationLikelihood = true

[MetricMap_ndtOccupancyMap_00_insertOpts]
resolution          = 0.35
occupancy_enabled   = false
p_hit               = 0.7
p_miss              = 0.45
logodds_min         = -3.25
logodds_max         = 4.5
min_range           = 0.3
max_range           = 25
ray_mode            = PerHitCell
decimation          = 3
decimation_3d_range = 4
min_eigen_ratio     = 0.02
min_eigen_abs       = 1e-05
threads             = 2

[MetricMap_ndtOccupancyMap_00_likelihoodOpts]
decimation          = 7
decimation_3d_range = 5
outlier_likelihood  = 0.125
search_neighbours   = false
min_range           = 0.5
max_range           = 12.5
scale               = 0.25
likelihood_method   = NdtMcl
ndt_mcl_scan_factor = 4
ndt_mcl_map_factor = 2
ndt_mcl_max_gaussians = 450
)ini";

mrpt::maps::CMultiMetricMap multiMapFrom(const std::string& text, const std::string& section) {
  mrpt::maps::TSetOfMetricMapInitializers inits;
  inits.loadFromConfigFile(mrpt::config::CConfigFileMemory(text), section);
  mrpt::maps::CMultiMetricMap map;
  map.setListOfMaps(inits);
  return map;
}

CNDTOccupancyMap::TInsertionOptions loadInsertion(const std::string& body) {
  CNDTOccupancyMap::TInsertionOptions o;
  o.loadFromConfigFile(mrpt::config::CConfigFileMemory("[s]\n" + body), "s");
  return o;
}

}  // namespace

TEST(IniOptions, ShortNameCreatesTheMapWithTheTextsOptions) {
  const auto multi = multiMapFrom(kIni, "MetricMap");
  ASSERT_EQ(multi.countMapsByClass<CNDTOccupancyMap>(), 1u);
  ASSERT_EQ(multi.countMapsByClass<mrpt::maps::CSimplePointsMap>(), 1u);
  const auto map = multi.mapByClass<CNDTOccupancyMap>();
  ASSERT_TRUE(map);

  const auto& in = map->insertionOptions;
  EXPECT_EQ(in.resolution, 0.35);
  EXPECT_FALSE(in.occupancy.enabled);
  EXPECT_EQ(in.occupancy.p_hit, 0.7);
  EXPECT_EQ(in.occupancy.p_miss, 0.45);
  EXPECT_EQ(in.occupancy.logodds_min, -3.25);
  EXPECT_EQ(in.occupancy.logodds_max, 4.5);
  EXPECT_EQ(in.scan.min_range, 0.3);
  EXPECT_EQ(in.scan.max_range, 25.0);
  EXPECT_EQ(in.scan.ray_mode, ndtom::RayMode::PerHitCell);
  EXPECT_EQ(in.decimation, 3u);
  EXPECT_EQ(in.decimation_3d_range, 4u);
  EXPECT_EQ(in.regularization.min_eigen_ratio, 0.02);
  EXPECT_EQ(in.regularization.min_eigen_abs, 1e-5);
  EXPECT_EQ(in.scan.threads, 2);

  const auto& lk = map->likelihoodOptions;
  EXPECT_EQ(lk.decimation, 7u);
  EXPECT_EQ(lk.decimation_3d_range, 5u);
  EXPECT_EQ(lk.outlier_likelihood, 0.125);
  EXPECT_FALSE(lk.search_neighbours);
  EXPECT_EQ(lk.min_range, 0.5);
  EXPECT_EQ(lk.max_range, 12.5);
  EXPECT_EQ(lk.scale, 0.25);
  EXPECT_EQ(lk.likelihood_method, CNDTOccupancyMap::TLikelihoodMethod::NdtMcl);
  EXPECT_EQ(lk.ndt_mcl_scan_factor, 4);
  EXPECT_EQ(lk.ndt_mcl_map_factor, 2);
  EXPECT_EQ(lk.ndt_mcl_max_gaussians, 450);

  EXPECT_FALSE(map->genericMapParams.enableSaveAs3DObject);
  // The core map already runs with these options.
  EXPECT_EQ(map->ndtMap().options().resolution, 0.35);
  EXPECT_FALSE(map->ndtMap().options().occupancy.enabled);
  EXPECT_EQ(map->ndtMap().options().scan.ray_mode, ndtom::RayMode::PerHitCell);
  EXPECT_EQ(map->ndtMap().options().scan.threads, 2);
}

TEST(IniOptions, DefaultsWhenSectionsAreMissing) {
  const auto multi = multiMapFrom("[M]\nndtOccupancyMap_count=1\n", "M");
  const auto map = multi.mapByClass<CNDTOccupancyMap>();
  ASSERT_TRUE(map);
  EXPECT_TRUE(map->insertionOptions == CNDTOccupancyMap::TInsertionOptions());
  EXPECT_TRUE(map->likelihoodOptions == CNDTOccupancyMap::TLikelihoodOptions());
  EXPECT_TRUE(map->genericMapParams.enableSaveAs3DObject);
}

TEST(IniOptions, FactoryKnowsBothNames) {
  for (const char* name : {"ndtOccupancyMap", "mrpt_ndtom::CNDTOccupancyMap"}) {
    std::unique_ptr<mrpt::maps::TMetricMapInitializer> def(
        mrpt::maps::TMetricMapInitializer::factory(name));
    ASSERT_TRUE(def) << name;
    EXPECT_EQ(def->getMetricMapClassType(), CLASS_ID(CNDTOccupancyMap));
  }
}

TEST(IniOptions, SaveLoadRoundTripIsExact) {
  const auto map = multiMapFrom(kIni, "MetricMap").mapByClass<CNDTOccupancyMap>();
  ASSERT_TRUE(map);
  mrpt::config::CConfigFileMemory saved;
  map->insertionOptions.saveToConfigFile(saved, "ins");
  map->likelihoodOptions.saveToConfigFile(saved, "lik");
  // Through the text, as a file would: MRPT cannot read values it wrote with a comment
  // back from the same in-memory object.
  const mrpt::config::CConfigFileMemory text(saved.getContent());
  CNDTOccupancyMap::TInsertionOptions ins;
  CNDTOccupancyMap::TLikelihoodOptions lik;
  ins.loadFromConfigFile(text, "ins");
  lik.loadFromConfigFile(text, "lik");
  EXPECT_TRUE(ins == map->insertionOptions) << saved.getContent();
  EXPECT_TRUE(lik == map->likelihoodOptions) << saved.getContent();
  EXPECT_EQ(ins.scan.threads, 2) << saved.getContent();

  // Defaults too (max_range 100, the machine's memory budget).
  mrpt::config::CConfigFileMemory defaults;
  CNDTOccupancyMap::TInsertionOptions().saveToConfigFile(defaults, "d");
  EXPECT_TRUE(loadInsertion(defaults.getContent().substr(defaults.getContent().find('\n') + 1)) ==
              CNDTOccupancyMap::TInsertionOptions());
}

TEST(IniOptions, DumpListsEveryOptionWithAComment) {
  std::ostringstream ins, lik;
  CNDTOccupancyMap::TInsertionOptions().dumpToTextStream(ins);
  CNDTOccupancyMap::TLikelihoodOptions().dumpToTextStream(lik);
  for (const char* key :
       {"resolution", "occupancy_enabled", "p_hit", "p_miss", "logodds_min", "logodds_max",
        "min_range", "max_range", "ray_mode", "decimation", "decimation_3d_range",
        "min_eigen_ratio", "min_eigen_abs", "threads", "memory_budget"})
    EXPECT_NE(ins.str().find(key), std::string::npos) << key;
  for (const char* key :
       {"likelihood_method", "decimation", "decimation_3d_range", "outlier_likelihood",
        "search_neighbours", "min_range", "max_range", "scale", "ndt_mcl_scan_factor",
        "ndt_mcl_map_factor", "ndt_mcl_max_gaussians"})
    EXPECT_NE(lik.str().find(key), std::string::npos) << key;
  EXPECT_NE(lik.str().find("Points"), std::string::npos) << "enum written by name";
  EXPECT_NE(ins.str().find("PerPoint"), std::string::npos) << "enum written by name";
  EXPECT_NE(ins.str().find("// Cell edge [m]"), std::string::npos) << ins.str();
  EXPECT_NE(ins.str().find("// Threads inserting a scan"), std::string::npos) << ins.str();
}

TEST(IniOptions, RayModeByNumberToo) {
  EXPECT_EQ(loadInsertion("ray_mode = 1").scan.ray_mode, ndtom::RayMode::PerHitCell);
  EXPECT_EQ(loadInsertion("ray_mode = 0").scan.ray_mode, ndtom::RayMode::PerPoint);
}

TEST(IniOptions, LikelihoodMethodByNameOrNumber) {
  const auto load = [](const std::string& body) {
    CNDTOccupancyMap::TLikelihoodOptions o;
    o.loadFromConfigFile(mrpt::config::CConfigFileMemory("[s]\n" + body), "s");
    return o.likelihood_method;
  };
  using M = CNDTOccupancyMap::TLikelihoodMethod;
  EXPECT_EQ(load(""), M::Points);
  EXPECT_EQ(load("likelihood_method = NdtMcl"), M::NdtMcl);
  EXPECT_EQ(load("likelihood_method = Points"), M::Points);
  EXPECT_EQ(load("likelihood_method = 1"), M::NdtMcl);
  EXPECT_EQ(load("likelihood_method = 0"), M::Points);
}

TEST(IniOptions, BadValuesFailAtLoadNamingTheOption) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"p_hit = 0.4", "p_hit"},
      {"p_miss = 0.6", "p_miss"},
      {"resolution = 0", "resolution"},
      {"logodds_min = 1", "logodds_min"},
      {"max_range = 0.1\nmin_range = 0.5", "max_range"},
      {"decimation = 0", "decimation"},
      {"decimation_3d_range = -2", "decimation_3d_range"},
      {"ray_mode = Sideways", "ray_mode"},
      {"ray_mode = 7", "ray_mode"},
      {"min_eigen_ratio = 2", "min_eigen_ratio"},
      {"memory_budget = 0.5", "memory_budget"},
      {"memory_budget = inf", "memory_budget"},
  };
  for (const auto& [body, option] : cases) {
    const std::string msg = thrownMessage([&] { loadInsertion(body); });
    EXPECT_NE(msg.find(option), std::string::npos) << body << " -> " << msg;
  }
  const std::vector<std::pair<std::string, std::string>> likelihood = {
      {"outlier_likelihood = 0", "outlier_likelihood"},
      {"outlier_likelihood = 1.5", "outlier_likelihood"},
      {"scale = -1", "scale"},
      {"decimation = 0", "decimation"},
      {"max_range = 0", "max_range"},
      {"likelihood_method = ndt_mcl", "likelihood_method"},
      {"likelihood_method = 2", "likelihood_method = 2"},
      {"ndt_mcl_scan_factor = 0", "[s] ndt_mcl_scan_factor = 0: must be in [1, 64]"},
      {"ndt_mcl_scan_factor = 65", "ndt_mcl_scan_factor = 65"},
      {"ndt_mcl_scan_factor = 2.5", "ndt_mcl_scan_factor = 2.5"},
      {"ndt_mcl_map_factor = 0", "[s] ndt_mcl_map_factor = 0: must be in [1, 64]"},
      {"ndt_mcl_map_factor = x", "ndt_mcl_map_factor = x"},
      {"ndt_mcl_max_gaussians = 0", "[s] ndt_mcl_max_gaussians = 0: must be in [1, 100000]"},
      {"ndt_mcl_max_gaussians = 1e3", "ndt_mcl_max_gaussians = 1e3"},
      {"ndt_mcl_max_gaussians = many", "ndt_mcl_max_gaussians = many"},
  };
  for (const auto& [body, option] : likelihood) {
    CNDTOccupancyMap::TLikelihoodOptions o;
    const std::string msg = thrownMessage(
        [&] { o.loadFromConfigFile(mrpt::config::CConfigFileMemory("[s]\n" + body), "s"); });
    EXPECT_NE(msg.find(option), std::string::npos) << body << " -> " << msg;
  }
  // Through the multi-map loader the section is named as well.
  const std::string msg = thrownMessage([] {
    multiMapFrom("[M]\nndtOccupancyMap_count=1\n[M_ndtOccupancyMap_00_insertOpts]\np_hit=2\n", "M");
  });
  EXPECT_NE(msg.find("M_ndtOccupancyMap_00_insertOpts"), std::string::npos) << msg;
}

TEST(IniOptions, ThreadsMustBeAnIntegerInTheCoresRange) {
  EXPECT_EQ(loadInsertion("").scan.threads, 1);
  EXPECT_EQ(loadInsertion("threads = 256").scan.threads, 256);
  // MRPT keeps "#" and ";" comments in the value (it strips only "//").
  EXPECT_EQ(loadInsertion("threads = 4   # four").scan.threads, 4);
  EXPECT_EQ(loadInsertion("threads = 3 ; three").scan.threads, 3);
  // MRPT's read_int would take the last three as 2, 1 and 2.
  for (const std::string value :
       {"0", "-3", "257", "100000", "4294967298", "1e3", "2.5", "two", "2 threads"}) {
    const std::string msg = thrownMessage([&] { loadInsertion("threads = " + value); });
    EXPECT_NE(msg.find("[s] threads = " + value + ":"), std::string::npos)
        << value << " -> " << msg;
  }
  EXPECT_NE(thrownMessage([] { loadInsertion("threads = 0"); }).find("must be in [1, 256]"),
            std::string::npos);
  // Set in code, the value is checked at the next insertion, which then changes nothing.
  CNDTOccupancyMap map(0.5);
  map.insertionOptions.scan.threads = 0;
  const std::string msg = thrownMessage([&] { map.insertPoints({{2, 0, 0}}, {0, 0, 0}); });
  EXPECT_NE(msg.find("threads = 0"), std::string::npos) << msg;
  EXPECT_TRUE(map.isEmpty());
}

TEST(IniOptions, ThreadsChangeWithoutRebuildingTheMap) {
  CNDTOccupancyMap map(0.5);
  map.insertPoints({{2, 0, 0}, {2, 0.05, 0}, {2, 0.1, 0.05}}, {0, 0, 0});
  const auto lookup = map.gaussianLookup();
  map.insertionOptions.scan.threads = 2;
  map.insertPoints({}, {0, 0, 0});  // no points: only the options are applied
  EXPECT_EQ(map.gaussianLookup(), lookup) << "the map was rebuilt";
  map.insertionOptions.occupancy.logodds_max = 3.0;  // a real change does rebuild it
  map.insertPoints({}, {0, 0, 0});
  EXPECT_NE(map.gaussianLookup(), lookup);
}

TEST(IniOptions, ResolutionIsFixedOnceTheMapHoldsData) {
  CNDTOccupancyMap map(0.5);
  map.insertionOptions.resolution = 0.25;  // empty map: taken at the next insertion
  map.insertPoints({{2, 0, 0}, {2, 0.01, 0}, {2, 0.02, 0.01}}, {0, 0, 0});
  EXPECT_EQ(map.ndtMap().options().resolution, 0.25);
  map.insertionOptions.resolution = 1.0;
  EXPECT_THROW(map.insertPoints({{3, 0, 0}}, {0, 0, 0}), std::exception);
  // Other options may change: the map is rebuilt with the new clamp.
  map.insertionOptions.resolution = 0.25;
  map.insertionOptions.occupancy.logodds_max = 0.1;
  map.insertPoints({{3, 0, 0}}, {0, 0, 0});
  map.ndtMap().forEachCell([](const ndtom::CellView& c) { EXPECT_LE(c.logodds, 0.1f); });
  map.clear();
  map.insertionOptions.resolution = 1.0;  // allowed again after clear()
  map.insertPoints({{3, 0, 0}}, {0, 0, 0});
  EXPECT_EQ(map.ndtMap().options().resolution, 1.0);
}

TEST(IniOptions, GenericFlagsFromCreationOptsAreHonoured) {
  const auto multi = multiMapFrom(
      "[M]\nndtOccupancyMap_count=1\n[M_ndtOccupancyMap_00_creationOpts]\n"
      "enableObservationInsertion=false\nenableObservationLikelihood=false\n",
      "M");
  const auto map = multi.mapByClass<CNDTOccupancyMap>();
  ASSERT_TRUE(map);
  mrpt::obs::CObservation2DRangeScan scan;
  scan.aperture = 1.0f;
  scan.resizeScan(3);
  for (size_t i = 0; i < 3; ++i) {
    scan.setScanRange(i, 2.0f);
    scan.setScanRangeValidity(i, true);
  }
  EXPECT_FALSE(map->insertObservation(scan));
  EXPECT_TRUE(map->isEmpty());
  map->genericMapParams.enableObservationInsertion = true;
  EXPECT_TRUE(map->insertObservation(scan));
  EXPECT_FALSE(map->isEmpty());
  EXPECT_FALSE(map->canComputeObservationLikelihood(scan)) << "likelihood disabled";
  map->genericMapParams.enableObservationLikelihood = true;
  EXPECT_TRUE(map->canComputeObservationLikelihood(scan));
}

TEST(IniOptions, AsStringDescribesTheMap) {
  CNDTOccupancyMap map(0.25);
  map.insertPoints({{2, 0, 0}, {2, 0.05, 0}, {2, 0.1, 0.05}}, {0, 0, 0});
  const std::string text = map.asString();
  EXPECT_NE(text.find("NDT-OM"), std::string::npos) << text;
  EXPECT_NE(text.find("resolution 0.25 m"), std::string::npos) << text;
  EXPECT_NE(text.find("1 Gaussians"), std::string::npos) << text;
}

TEST(IniOptions, RenderOptionsFromTheirSection) {
  const auto multi = multiMapFrom(R"ini(
[M]
ndtOccupancyMap_count = 1
[M_ndtOccupancyMap_00_renderOpts]
quantiles = 2.5
subdivisions = 3
max_ellipsoids = 1234
min_logodds = 0.5
color_min_z = -1
color_max_z = 4
colormap = cmHOT
show_free_cells = true
max_free_cells = 99
free_cell_point_size = 3.5
generate_occupied_voxels = false
visible_occupied_voxels = false
generate_free_voxels = false
visible_free_voxels = false
)ini",
                                  "M");
  const auto map = multi.mapByClass<CNDTOccupancyMap>();
  ASSERT_TRUE(map);
  const mrpt_ndtom::TRenderOptions& r = map->renderOptions;
  EXPECT_EQ(r.quantiles, 2.5);
  EXPECT_EQ(r.subdivisions, 3u);
  EXPECT_EQ(r.max_ellipsoids, 1234u);
  EXPECT_EQ(r.min_logodds, 0.5);
  EXPECT_EQ(r.color_min_z, -1.0);
  EXPECT_EQ(r.color_max_z, 4.0);
  EXPECT_EQ(r.colormap, mrpt::img::cmHOT);
  EXPECT_TRUE(r.show_free_cells);
  EXPECT_EQ(r.max_free_cells, 99u);
  EXPECT_EQ(r.free_cell_point_size, 3.5f);
  EXPECT_FALSE(r.generate_occupied_voxels || r.visible_occupied_voxels ||
               r.generate_free_voxels || r.visible_free_voxels);

  // Saved and read back through text: the same options.
  mrpt::config::CConfigFileMemory saved;
  r.saveToConfigFile(saved, "r");
  mrpt_ndtom::TRenderOptions again;
  again.loadFromConfigFile(mrpt::config::CConfigFileMemory(saved.getContent()), "r");
  EXPECT_TRUE(again == r) << saved.getContent();

  // Bad values name the section and the option, and change nothing.
  for (const auto& [body, option] :
       std::vector<std::pair<std::string, std::string>>{{"subdivisions = 9", "subdivisions"},
                                                        {"quantiles = -1", "quantiles"},
                                                        {"colormap = cmRAINBOW", "colormap"},
                                                        {"max_ellipsoids = -3", "max_ellipsoids"},
                                                        {"free_cell_point_size = 0", "free_cell"}}) {
    mrpt_ndtom::TRenderOptions o;
    const std::string msg = thrownMessage(
        [&] { o.loadFromConfigFile(mrpt::config::CConfigFileMemory("[s]\n" + body), "s"); });
    EXPECT_NE(msg.find(option), std::string::npos) << body << " -> " << msg;
    EXPECT_TRUE(o == mrpt_ndtom::TRenderOptions()) << body;
  }
}

TEST(IniOptions, DumpPutsEachOptionGroupUnderItsHeader) {
  mrpt::maps::TSetOfMetricMapInitializers inits;
  inits.loadFromConfigFile(mrpt::config::CConfigFileMemory(kIni), "MetricMap");
  std::ostringstream out;
  inits.dumpToTextStream(out);
  const std::string text = out.str();
  const size_t insertion = text.find("[CNDTOccupancyMap::TInsertionOptions]");
  const size_t likelihood = text.find("[CNDTOccupancyMap::TLikelihoodOptions]");
  const size_t render = text.find("[mrpt_ndtom::TRenderOptions]");
  ASSERT_NE(insertion, std::string::npos) << text;
  ASSERT_NE(likelihood, std::string::npos) << text;
  ASSERT_NE(render, std::string::npos) << text;
  EXPECT_LT(insertion, likelihood);
  EXPECT_LT(likelihood, render);
  // decimation and the ranges appear once in each of the first two groups, under its header.
  for (const char* key : {"decimation ", "min_range", "max_range"}) {
    const size_t first = text.find(key, insertion), second = text.find(key, likelihood);
    EXPECT_LT(first, likelihood) << key;
    EXPECT_LT(second, render) << key;
  }
  EXPECT_NE(text.find("ray_mode", insertion), std::string::npos);
  EXPECT_LT(text.find("ray_mode", insertion), likelihood);
  EXPECT_GT(text.find("quantiles"), render);
}
