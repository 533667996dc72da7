// CMetricMapBuilderNDT::TConfigParams as .ini text: every key read as written, save -> load
// gives the same options, bad values fail naming the section and the key (and change
// nothing), and the shipped share/mrpt/ndtom-slam.ini loads.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <sstream>

#include "mrpt_ndtom/CMetricMapBuilderNDT.h"
#include "support/thrown_message.h"

using mrpt_ndtom::CMetricMapBuilderNDT;
using ndtom::testing::thrownMessage;
using Params = CMetricMapBuilderNDT::TConfigParams;

namespace {

// Every key, none at its default.
const char* kIni = R"ini(
[slam]
method               = d2d
level_factors        = 8 4 2
outlier_ratio        = 0.5
max_iterations       = 20
translation_epsilon  = 0.001
rotation_epsilon     = 0.002
min_range            = 0.5
max_range            = 40
voxel_ratio          = 0.25
max_points           = 3000
min_matched_fraction = 0.3
min_judged_fraction  = 0.2
max_free_fraction    = 0.125
planar               = true
threads              = 3
recovery_radius      = 3
recovery_yaw_deg     = 45
weak_direction_sigma = 0.25
ground_thinning      = 50
retry_without_finest = false
target_radius        = 30
target_refresh_distance  = 1.5
free_space_overrule  = 0.25

[slam_ndtOccupancyMap_00_insertOpts]
resolution = 0.25
max_range  = 20
decimation = 2
)ini";

Params load(const std::string& text, const std::string& section = "slam") {
  Params o;
  o.loadFromConfigFile(mrpt::config::CConfigFileMemory(text), section);
  return o;
}

}  // namespace

TEST(MapBuilderOptions, EveryKeyIsReadAsWritten) {
  const Params o = load(kIni);
  const auto& r = o.online.placement.registration;
  EXPECT_EQ(r.method, ndtom::RegistrationMethod::D2D);
  EXPECT_EQ(r.level_factors, (std::vector<int>{8, 4, 2}));
  EXPECT_EQ(r.outlier_ratio, 0.5);
  EXPECT_EQ(r.max_iterations, 20);
  EXPECT_EQ(r.translation_epsilon, 0.001);
  EXPECT_EQ(r.rotation_epsilon, 0.002);
  EXPECT_EQ(r.min_range, 0.5);
  EXPECT_EQ(r.max_range, 40);
  EXPECT_EQ(r.voxel_ratio, 0.25);
  EXPECT_EQ(r.max_points, 3000u);
  EXPECT_EQ(r.min_matched_fraction, 0.3);
  EXPECT_EQ(r.min_judged_fraction, 0.2);
  EXPECT_EQ(r.max_free_fraction, 0.125);
  EXPECT_TRUE(r.planar);
  EXPECT_EQ(o.online.threads, 3);
  const auto& p = o.online.placement;
  EXPECT_EQ(p.recovery_radius, 3);
  EXPECT_EQ(p.recovery_yaw_deg, 45);
  EXPECT_EQ(p.weak_direction_sigma, 0.25);
  EXPECT_EQ(p.ground_thinning, 50);
  EXPECT_FALSE(p.retry_without_finest);
  EXPECT_EQ(o.online.target_radius, 30);
  EXPECT_EQ(o.online.target_refresh_distance, 1.5);
  EXPECT_EQ(o.online.free_space_overrule, 0.25);
  EXPECT_EQ(o.mapOptions.resolution, 0.25);
  EXPECT_EQ(o.mapOptions.scan.max_range, 20);
  EXPECT_EQ(o.mapOptions.decimation, 2u);
  EXPECT_FALSE(o == Params()) << "every value differs from the defaults";
}

TEST(MapBuilderOptions, AbsentKeysKeepTheOnlineMappersDefaults) {
  const Params o = load("[slam]\n");
  const ndtom::OnlineMapperOptions core;
  EXPECT_EQ(o.online.placement.registration.level_factors,
            core.placement.registration.level_factors);
  EXPECT_EQ(o.online.placement.registration.min_matched_fraction,
            core.placement.registration.min_matched_fraction);
  EXPECT_EQ(o.online.placement.recovery_radius, core.placement.recovery_radius);
  EXPECT_EQ(o.online.target_radius, core.target_radius);
  EXPECT_EQ(o.online.threads, core.threads);
  EXPECT_TRUE(o.mapOptions == mrpt_ndtom::CNDTOccupancyMap::TInsertionOptions());
  EXPECT_TRUE(o == Params());
}

TEST(MapBuilderOptions, SaveThenLoadGivesTheSameOptions) {
  const Params original = load(kIni);
  mrpt::config::CConfigFileMemory saved;
  original.saveToConfigFile(saved, "other");
  const Params again = load(saved.getContent(), "other");
  EXPECT_TRUE(again == original) << saved.getContent();
  EXPECT_TRUE(saved.sectionExists("other_ndtOccupancyMap_00_insertOpts"));
  // The values themselves, not only operator==.
  EXPECT_EQ(again.online.placement.registration.level_factors, (std::vector<int>{8, 4, 2}));
  EXPECT_EQ(again.online.target_refresh_distance, 1.5);
  EXPECT_EQ(again.online.free_space_overrule, 0.25);
  EXPECT_EQ(again.mapOptions.resolution, 0.25);
  // An infinite sigma ("never keep the prediction") survives too.
  Params never = original;
  never.online.placement.weak_direction_sigma = std::numeric_limits<double>::infinity();
  mrpt::config::CConfigFileMemory saved_inf;
  never.saveToConfigFile(saved_inf, "s");
  EXPECT_TRUE(load(saved_inf.getContent(), "s") == never) << saved_inf.getContent();
}

TEST(MapBuilderOptions, TheKeysAreThoseSaved) {
  const auto keys = Params::keys();
  for (const char* key : {"level_factors", "planar", "recovery_radius", "target_radius",
                          "target_refresh_distance", "threads", "max_free_fraction",
                          "retry_without_finest", "free_space_overrule"})
    EXPECT_NE(std::find(keys.begin(), keys.end(), key), keys.end()) << key;
  EXPECT_EQ(std::find(keys.begin(), keys.end(), "resolution"), keys.end())
      << "the map's keys are in its own section";
}

TEST(MapBuilderOptions, BadValuesNameTheSectionAndTheKey) {
  const auto message = [](const std::string& text) { return thrownMessage([&] { load(text); }); };
  struct Case {
    std::string text, section, key;
  };
  const std::vector<Case> cases = {
      {"[slam]\ntarget_radius = 50abc\n", "[slam]", "target_radius"},
      {"[slam]\ntarget_radius = -1\n", "[slam]", "target_radius"},
      {"[slam]\nrecovery_radius = nan\n", "[slam]", "recovery_radius"},
      {"[slam]\ntarget_refresh_distance = -2\n", "[slam]", "target_refresh_distance"},
      {"[slam]\nfree_space_overrule = -0.1\n", "[slam]", "free_space_overrule"},
      {"[slam]\nground_thinning = 2.5\n", "[slam]", "ground_thinning"},
      {"[slam]\nplanar = on\n", "[slam]", "planar"},
      {"[slam]\nretry_without_finest = maybe\n", "[slam]", "retry_without_finest"},
      {"[slam]\nlevel_factors = 2 4\n", "[slam]", "level_factors"},
      {"[slam]\nthreads = 0\n", "[slam]", "threads"},
      {"[slam]\n[slam_ndtOccupancyMap_00_insertOpts]\nresolution = -0.2\n",
       "[slam_ndtOccupancyMap_00_insertOpts]", "resolution"},
  };
  for (const Case& c : cases) {
    const std::string m = message(c.text);
    EXPECT_NE(m.find(c.section), std::string::npos) << c.text << " -> " << m;
    EXPECT_NE(m.find(c.key), std::string::npos) << c.text << " -> " << m;
  }
}

TEST(MapBuilderOptions, ABadValueChangesNothing) {
  Params o = load(kIni);
  const Params before = o;
  EXPECT_ANY_THROW(o.loadFromConfigFile(
      mrpt::config::CConfigFileMemory("[slam]\ntarget_radius = 5\nrecovery_radius = x\n"), "slam"));
  EXPECT_TRUE(o == before);
}

TEST(MapBuilderOptions, TheShippedFileLoads) {
  Params o;
  o.loadFromConfigFile(
      mrpt::config::CConfigFile(std::string(NDTOM_SOURCE_DIR) + "/share/mrpt/ndtom-slam.ini"),
      "NDTSLAM");
  EXPECT_TRUE(o.online.placement.registration.planar);
  EXPECT_EQ(o.online.placement.registration.level_factors, (std::vector<int>{16, 8, 4, 2}));
  EXPECT_EQ(o.online.placement.registration.max_free_fraction, 0.2);
  EXPECT_TRUE(std::isinf(o.online.placement.registration.max_range));
  EXPECT_EQ(o.mapOptions.resolution, 0.2);
  EXPECT_EQ(o.mapOptions.scan.max_range, 30);
  std::ostringstream dump;
  o.dumpToTextStream(dump);
  EXPECT_NE(dump.str().find("recovery_radius"), std::string::npos) << dump.str();
}
