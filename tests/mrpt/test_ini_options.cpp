// CNDTOccupancyMap from .ini text through MRPT's own machinery (TSetOfMetricMapInitializers,
// CMultiMetricMap): the options read back equal the text, survive save -> load, and bad
// values fail at load time with the option's name.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cmath>
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
      {"likelihood_method = 2", "[s] likelihood_method: expected Points or NdtMcl, got '2'"},
      {"ndt_mcl_scan_factor = 0", "[s] ndt_mcl_scan_factor = 0: must be in [1, 64]"},
      {"ndt_mcl_scan_factor = 65", "ndt_mcl_scan_factor = 65"},
      {"ndt_mcl_scan_factor = 2.5", "[s] ndt_mcl_scan_factor: not an integer: '2.5'"},
      {"ndt_mcl_map_factor = 0", "[s] ndt_mcl_map_factor = 0: must be in [1, 64]"},
      {"ndt_mcl_map_factor = x", "[s] ndt_mcl_map_factor: not an integer: 'x'"},
      {"ndt_mcl_max_gaussians = 0", "[s] ndt_mcl_max_gaussians = 0: must be in [1, 100000]"},
      {"ndt_mcl_max_gaussians = 1e3", "[s] ndt_mcl_max_gaussians: not an integer: '1e3'"},
      {"ndt_mcl_max_gaussians = many", "[s] ndt_mcl_max_gaussians: not an integer: 'many'"},
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
  // MRPT's read_int would take these as 2, 1, 2 and 2.
  for (const std::string value : {"0", "-3", "257", "100000", "4294967298"}) {
    const std::string msg = thrownMessage([&] { loadInsertion("threads = " + value); });
    EXPECT_NE(msg.find("[s] threads = " + value + ": must be in [1, 256]"), std::string::npos)
        << value << " -> " << msg;
  }
  for (const std::string value : {"1e3", "2.5", "two", "2 threads", "4#four"}) {
    const std::string msg = thrownMessage([&] { loadInsertion("threads = " + value); });
    EXPECT_NE(msg.find("[s] threads: not an integer: '" + value + "'"), std::string::npos)
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

namespace {

// The message of a load of `body` into a fresh T's section "s"; "" if it loads.
template <class T>
std::string loadError(const std::string& body) {
  T o;
  return thrownMessage(
      [&] { o.loadFromConfigFile(mrpt::config::CConfigFileMemory("[s]\n" + body), "s"); });
}

template <class T>
void expectRefusals(const std::vector<std::pair<std::string, std::string>>& cases) {
  for (const auto& [body, message] : cases) {
    const std::string msg = loadError<T>(body);
    EXPECT_NE(msg.find("Message:  " + message + "\n"), std::string::npos) << body << " -> " << msg;
  }
}

}  // namespace

// #38: MRPT's read_bool, read_int, read_double and read_enum took each of these for a value
// (in the comments); the plugin reads every key with the core's reader, as ndtom-map's
// --config and flags do, and refuses them in one line naming the section, key and text.
TEST(IniOptions, HostileInsertionValuesAreRefused) {
  expectRefusals<CNDTOccupancyMap::TInsertionOptions>({
      {"occupancy_enabled = on",
       "[s] occupancy_enabled: expected true or false, got 'on'"},  // false
      {"occupancy_enabled = maybe", "[s] occupancy_enabled: expected true or false, got 'maybe'"},
      {"occupancy_enabled = 2", "[s] occupancy_enabled: expected true or false, got '2'"},  // true
      {"decimation = 4294967298", "[s] decimation = 4294967298: must be in [1, 2147483647]"},  // 2
      {"decimation = 2.5", "[s] decimation: not an integer: '2.5'"},                           // 2
      {"decimation = -0", "[s] decimation = -0: must be in [1, 2147483647]"},
      {"decimation_3d_range = 3x", "[s] decimation_3d_range: not an integer: '3x'"},     // 3
      {"resolution = 0.2abc", "[s] resolution: not a number: '0.2abc'"},                 // 0.2
      {"max_range = 100m", "[s] max_range: not a number: '100m'"},                       // 100
      {"resolution =", "[s] resolution: not a number: ''"},                              // 0
      {"resolution = # cell edge", "[s] resolution: not a number: ''"},                  // 0
      {"threads = 3x", "[s] threads: not an integer: '3x'"},                             // 3
      {"min_eigen_abs = 1e400", "[s] min_eigen_abs: out of a double's range: '1e400'"},  // inf
      {"min_eigen_abs = inf", "[s] min_eigen_abs: must be finite, got 'inf'"},
      {"p_hit = nan", "[s] p_hit: not a number: 'nan'"},
      {"p_hit = 0.7;0.8", "[s] p_hit: not a number: '0.7;0.8'"},  // 0.7
      {"ray_mode = PerHitCell fast",
       "[s] ray_mode: expected PerPoint or PerHitCell, got "
       "'PerHitCell fast'"},  // the first word
      {"ray_mode = 1x", "[s] ray_mode: expected PerPoint or PerHitCell, got '1x'"},
  });
}

TEST(IniOptions, HostileLikelihoodAndRenderValuesAreRefused) {
  expectRefusals<CNDTOccupancyMap::TLikelihoodOptions>({
      {"search_neighbours = on", "[s] search_neighbours: expected true or false, got 'on'"},
      {"decimation = 4294967298", "[s] decimation = 4294967298: must be in [1, 2147483647]"},
      {"max_range = 12abc", "[s] max_range: not a number: '12abc'"},
      {"outlier_likelihood =", "[s] outlier_likelihood: not a number: ''"},
      {"min_range = 1e-400", "[s] min_range: out of a double's range: '1e-400'"},
      {"scale = 0.5x", "[s] scale: not a number: '0.5x'"},
      // pf-localization aborted on this: see TLikelihoodOptions::kMaxScale.
      {"scale = 1e308",
       "[s] scale = 1e+308: must be in (0, 1e+280], which keeps a particle "
       "filter's log-likelihoods finite"},
      {"scale = 0",
       "[s] scale = 0: must be in (0, 1e+280], which keeps a particle filter's "
       "log-likelihoods finite"},
      {"likelihood_method = 1x", "[s] likelihood_method: expected Points or NdtMcl, got '1x'"},
      {"likelihood_method = NdtMcl fast",
       "[s] likelihood_method: expected Points or NdtMcl, got 'NdtMcl fast'"},
  });
  expectRefusals<mrpt_ndtom::TRenderOptions>({
      {"show_free_cells = 2", "[s] show_free_cells: expected true or false, got '2'"},
      {"quantiles = 2.5x", "[s] quantiles: not a number: '2.5x'"},
      {"color_min_z = inf", "[s] color_min_z: must be finite, got 'inf'"},
      {"free_cell_point_size = 1e39", "[s] free_cell_point_size = inf: must be finite and > 0"},
      {"max_free_cells = 4294967296",
       "[s] max_free_cells = 4294967296: must be in [0, 4294967295]"},
      {"subdivisions = 2.0", "[s] subdivisions: not an integer: '2.0'"},
  });
  const std::string colormap = loadError<mrpt_ndtom::TRenderOptions>("colormap = 99");
  EXPECT_NE(colormap.find("[s] colormap: expected cm"), std::string::npos) << colormap;
  EXPECT_NE(colormap.find(", got '99'\n"), std::string::npos) << colormap;
}

// What a person writes around a value: a comment after a blank, capitals in a bool, an
// explicit sign, an infinite range, nan where it means "from the map".
TEST(IniOptions, CommentsCapitalsAndNonFiniteWhereMeantStillLoad) {
  const auto in = loadInsertion(
      "resolution = 0.25 # m\noccupancy_enabled = TRUE\nmax_range = inf ; no limit\n"
      "decimation = +4\nray_mode = PerHitCell   # faster\n");
  EXPECT_EQ(in.resolution, 0.25);
  EXPECT_TRUE(in.occupancy.enabled);
  EXPECT_EQ(in.scan.max_range, INFINITY);
  EXPECT_EQ(in.decimation, 4u);
  EXPECT_EQ(in.scan.ray_mode, ndtom::RayMode::PerHitCell);
  EXPECT_FALSE(loadInsertion("occupancy_enabled = No").occupancy.enabled);

  CNDTOccupancyMap::TLikelihoodOptions lik;
  lik.loadFromConfigFile(
      mrpt::config::CConfigFileMemory("[s]\nsearch_neighbours = no # one cell\nmax_range = 30 ; m\n"
                                      "likelihood_method = NdtMcl ; per particle\n"),
      "s");
  EXPECT_FALSE(lik.search_neighbours);
  EXPECT_EQ(lik.max_range, 30.0);
  EXPECT_EQ(lik.likelihood_method, CNDTOccupancyMap::TLikelihoodMethod::NdtMcl);
  lik.loadFromConfigFile(mrpt::config::CConfigFileMemory("[s]\nscale = 1e280\n"), "s");
  EXPECT_EQ(lik.scale, CNDTOccupancyMap::TLikelihoodOptions::kMaxScale);

  mrpt_ndtom::TRenderOptions render;
  render.color_min_z = 1;
  render.loadFromConfigFile(
      mrpt::config::CConfigFileMemory("[s]\ncolor_min_z = nan\nmin_logodds = -inf\n"
                                      "colormap = 2 # by number\n"),
      "s");
  EXPECT_TRUE(std::isnan(render.color_min_z));
  EXPECT_EQ(render.min_logodds, -INFINITY);
  EXPECT_EQ(int(render.colormap), 2);
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
  EXPECT_FALSE(r.generate_occupied_voxels || r.visible_occupied_voxels || r.generate_free_voxels ||
               r.visible_free_voxels);

  // Saved and read back through text: the same options.
  mrpt::config::CConfigFileMemory saved;
  r.saveToConfigFile(saved, "r");
  mrpt_ndtom::TRenderOptions again;
  again.loadFromConfigFile(mrpt::config::CConfigFileMemory(saved.getContent()), "r");
  EXPECT_TRUE(again == r) << saved.getContent();

  // Bad values name the section and the option, and change nothing.
  for (const auto& [body, option] : std::vector<std::pair<std::string, std::string>>{
           {"subdivisions = 9", "subdivisions"},
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
