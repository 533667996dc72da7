// The pieces of ndtom-map that decide what gets mapped: the input's options, option layering
// (defaults < .ini file < command line), trajectory matching, statistics and JSON text.
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>

#include "mapper_run.h"
#include "ndtom_apps/input_format.h"
#include "ndtom_apps/insertion_settings.h"
#include "ndtom_apps/json_writer.h"
#include "ndtom_apps/mpi_options.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_apps/scan_source.h"
#include "ndtom_apps/trajectory_poses.h"
#include "run_summary.h"

using namespace ndtom::apps;
using namespace ndtom::mapper;
using mapper_test::TempDir;

// The strict value parsers are tested with the rest of libs/ndtom_apps (tests/apps).
TEST(ErrorMessages, OneLineOfAnMrptException) {
  try {
    THROW_EXCEPTION("[section] p_hit = 2: must be in (0.5, 1)");
  } catch (const std::exception& e) {
    EXPECT_EQ(ndtom::apps::oneLineMessage(e), "[section] p_hit = 2: must be in (0.5, 1)");
  }
}

// The options ndtom-map and ndtom-localize name their input and outputs with.
TEST(InputOptions, SetTheInputAndPrefix) {
  struct Options {
    std::string prefix, poses_file;
    InputFormat format = InputFormat::Auto;
    ndtom::io::PoseFormat pose_format = ndtom::io::PoseFormat::Auto;
  };
  const auto table = withInputOptions<Options>({});
  const char* argv[] = {"program", "in",      "--output", "out",           "--format",
                        "tum",     "--poses", "p.txt",    "--pose-format", "kitti"};
  Options o;
  EXPECT_EQ(applyArguments(10, argv, table, o), std::vector<std::string>{"in"});
  EXPECT_EQ(o.prefix, "out");
  EXPECT_EQ(o.format, InputFormat::TumRgbd);
  EXPECT_EQ(o.poses_file, "p.txt");
  EXPECT_EQ(o.pose_format, ndtom::io::PoseFormat::Kitti);
  const char* short_prefix[] = {"program", "-o", "x"};
  applyArguments(3, short_prefix, table, o);
  EXPECT_EQ(o.prefix, "x");
  EXPECT_EQ(poseFormatFromName("--reference-format", "tum"), ndtom::io::PoseFormat::Tum);
  try {
    poseFormatFromName("--pose-format", "kiti");
    FAIL();
  } catch (const UsageError& e) {
    EXPECT_STREQ(e.what(), "--pose-format: expected auto, kitti or tum, got 'kiti'");
  }
}

TEST(InsertionSettings, FileThenCommandLine) {
  TempDir dir;
  InsertionOptions in_file;
  in_file.resolution = 0.35;
  in_file.occupancy.p_hit = 0.7;
  in_file.occupancy.logodds_min = -3;
  in_file.scan.max_range = 25;
  in_file.scan.ray_mode = ndtom::RayMode::PerHitCell;
  in_file.decimation = 3;
  in_file.occupancy.enabled = false;
  in_file.scan.threads = 3;
  mrpt::config::CConfigFileMemory memory;
  in_file.saveToConfigFile(memory, "Mine");
  std::ofstream(dir / "map.ini") << memory.getContent();

  InsertionSettings settings;
  settings.config_file = (dir / "map.ini").string();
  settings.section = "Mine";
  EXPECT_TRUE(resolveInsertionOptions(settings) == in_file);

  settings.overrides = {
      {"p_hit", "0.65"}, {"max_range", "inf"}, {"ray_mode", "PerPoint"}, {"threads", "2"}};
  InsertionOptions expected = in_file;
  expected.scan.threads = 2;
  expected.occupancy.p_hit = 0.65;
  expected.scan.max_range = std::numeric_limits<double>::infinity();
  expected.scan.ray_mode = ndtom::RayMode::PerPoint;
  EXPECT_TRUE(resolveInsertionOptions(settings) == expected);

  // Every key --help lists is one the plugin saves, and the other way round.
  std::vector<std::string> saved;
  memory.getAllKeys("Mine", saved);
  EXPECT_EQ(saved.size(), insertionKeys().size());
  for (const auto& key : insertionKeys()) EXPECT_TRUE(isInsertionKey(key.name));
}

// #38: a value in the --config file and the same text as a flag go through one reader (the
// plugin's .ini loader and the flags both use ndtom/map/option_text.h): both give the same
// options, or both are refused naming the key.
TEST(InsertionSettings, FileAndFlagsTakeTheSameTexts) {
  TempDir dir;
  const std::vector<std::pair<std::string, std::string>> texts = {{"occupancy_enabled", "on"},
                                                                  {"occupancy_enabled", "maybe"},
                                                                  {"occupancy_enabled", "2"},
                                                                  {"occupancy_enabled", "TRUE"},
                                                                  {"occupancy_enabled", "no"},
                                                                  {"decimation", "4294967298"},
                                                                  {"decimation", "2.5"},
                                                                  {"decimation", "-0"},
                                                                  {"decimation", "+3"},
                                                                  {"resolution", "0.2abc"},
                                                                  {"resolution", "0.2"},
                                                                  {"resolution", ""},
                                                                  {"max_range", "100m"},
                                                                  {"max_range", "inf"},
                                                                  {"min_eigen_abs", "1e400"},
                                                                  {"threads", "3x"},
                                                                  {"threads", "3"},
                                                                  {"ray_mode", "PerHitCell x"},
                                                                  {"ray_mode", "1"},
                                                                  {"memory_budget", "1e400"},
                                                                  {"p_hit", "nan"}};
  for (const auto& [key, text] : texts) {
    std::ofstream(dir / "map.ini") << "[s]\n" << key << " = " << text << "\n";
    InsertionSettings file, flag;
    file.config_file = (dir / "map.ini").string();
    file.section = "s";
    flag.overrides = {{key, text}};
    InsertionOptions from_file, from_flag;
    std::string file_error, flag_error;
    try {
      from_file = resolveInsertionOptions(file);
    } catch (const UsageError& e) {
      file_error = e.what();
    }
    try {
      from_flag = resolveInsertionOptions(flag);
    } catch (const UsageError& e) {
      flag_error = e.what();
    }
    const std::string what = key + " = '" + text + "': " + file_error + " | " + flag_error;
    ASSERT_EQ(file_error.empty(), flag_error.empty()) << what;
    if (file_error.empty()) {
      EXPECT_TRUE(from_file == from_flag) << what;
    } else {
      std::string option = "--" + key;
      std::replace(option.begin(), option.end(), '_', '-');
      EXPECT_NE(file_error.find("[s] " + key), std::string::npos) << what;
      EXPECT_NE(flag_error.find(option), std::string::npos) << what;
    }
  }
  // Only a file has comments: MRPT leaves "# ..." and "; ..." in the value.
  std::ofstream(dir / "map.ini") << "[s]\nthreads = 3 # three\nresolution = 0.25 ; m\n";
  InsertionSettings file;
  file.config_file = (dir / "map.ini").string();
  file.section = "s";
  const InsertionOptions commented = resolveInsertionOptions(file);
  EXPECT_EQ(commented.scan.threads, 3);
  EXPECT_EQ(commented.resolution, 0.25);
}

TEST(TrajectoryPoses, TumMatchesTheNearestTimeWithinTheTolerance) {
  TempDir dir;
  std::ofstream(dir / "t.txt") << "# t x y z qx qy qz qw\n"
                                  "10.00 1 0 0 0 0 0 1\n"
                                  "10.50 2 0 0 0 0 0 1\n"
                                  "10.25 3 0 0 0 0 0 1\n";  // out of order on purpose
  const TrajectoryPoses poses((dir / "t.txt").string(), ndtom::io::PoseFormat::Auto, 0.05);
  EXPECT_TRUE(poses.matchesByTime());
  EXPECT_EQ(poses.poseFor(0, 10.01).translation().x(), 1);
  EXPECT_EQ(poses.poseFor(0, 10.28).translation().x(), 3);
  EXPECT_EQ(poses.poseFor(0, 10.46).translation().x(), 2);
  EXPECT_NO_THROW(poses.checkCovers({10.0, 10.29, 10.54}, "log"));
  EXPECT_THROW(poses.checkCovers({10.0, 10.38}, "log"), InputError);
}

TEST(TrajectoryPoses, KittiMatchesLineByLine) {
  TempDir dir;
  std::ofstream(dir / "k.txt") << "1 0 0 5 0 1 0 0 0 0 1 0\n1 0 0 6 0 1 0 0 0 0 1 0\n";
  const TrajectoryPoses poses((dir / "k.txt").string(), ndtom::io::PoseFormat::Auto, 0.05);
  EXPECT_FALSE(poses.matchesByTime());
  EXPECT_EQ(poses.poseFor(1, 123.0).translation().x(), 6);
  EXPECT_NO_THROW(poses.checkCovers({0, 0}, "log"));
  EXPECT_THROW(poses.checkCovers({0, 0, 0}, "log"), InputError);
}

TEST(RunSummary, Drift) {
  std::vector<PassResult> passes(3);
  passes[0].cells = 1000, passes[1].cells = 1000, passes[2].cells = 1010;
  passes[0].map_bytes = 200, passes[1].map_bytes = 199, passes[2].map_bytes = 200;
  const PassDrift d = passDrift(passes);
  EXPECT_DOUBLE_EQ(d.cells_percent, 1.0);
  EXPECT_DOUBLE_EQ(d.map_bytes_percent, 0.5);
}

TEST(JsonWriter, NestedObjectsAndQuoting) {
  JsonWriter j;
  j.beginObject();
  j.field("path", std::string("a \"b\"\\c\n"));
  j.beginObject("map");
  j.field("cells", size_t(12));
  j.field("inf", std::numeric_limits<double>::infinity());
  j.endObject();
  j.beginArray("passes");
  j.beginObject();
  j.field("ok", true);
  j.endObject();
  j.endArray();
  j.endObject();
  EXPECT_EQ(j.str(),
            "{\n  \"path\": \"a \\\"b\\\"\\\\c\\u000a\",\n  \"map\": {\n    \"cells\": 12,\n"
            "    \"inf\": null\n  },\n  \"passes\": [\n    {\n      \"ok\": true\n    }\n  ]\n}\n");
}

TEST(MpiOptions, RankTilesDefaultFollowsTheRayShareAndAGivenValueWins) {
  using ndtom::mapper::RayShare;
  const auto parse = [](std::vector<const char*> args) {
    args.insert(args.begin(), {"ndtom-map-mpi", "in", "-o", "out"});
    return ndtom::mapper::parseMpiOptions(int(args.size()), const_cast<char**>(args.data()));
  };
  const auto rays = parse({});
  EXPECT_EQ(rays.ray_share, RayShare::Rays);
  EXPECT_EQ(rays.rank_tiles, ndtom::mapper::defaultRankTiles(RayShare::Rays));
  EXPECT_EQ(parse({"--ray-share", "tiles"}).rank_tiles, 4);
  EXPECT_EQ(parse({"--ray-share", "rays"}).rank_tiles, 1);
  EXPECT_EQ(parse({"--rank-tiles", "3", "--ray-share", "tiles"}).rank_tiles, 3);
  EXPECT_EQ(parse({"--ray-share", "rays", "--rank-tiles", "4"}).rank_tiles, 4);
}
