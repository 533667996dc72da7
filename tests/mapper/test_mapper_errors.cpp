// Every kind of bad input gives a one-line message naming the file or option, a non-zero
// exit code (1: bad data, 2: bad command line), and no output file at all under the prefix,
// even when the failure comes after some scans were mapped.
#include <map>

#include "mapper_run.h"
#include "support/special_files.h"

using namespace mapper_test;

namespace {

struct Case {
  std::string args;  ///< after the input and -o
  int exit_code;
  std::string message;  ///< must appear in the one line on stderr
};

void copyLidarScans(const fs::path& to) {
  fs::create_directories(to);
  for (int i = 0; i < 10; ++i) {
    const std::string name = "full" + std::to_string(i) + ".pcd";
    fs::copy_file(kLidar + "/" + name, to / name);
  }
}

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// Runs ndtom-map on `input` with `c.args` and checks the outcome.
void expectFailure(const TempDir& dir, const std::string& input, const Case& c) {
  SCOPED_TRACE(input + " " + c.args);
  const ProgramRun run =
      runMapper(quoted(input) + " -o " + quoted((dir / "out").string()) + " -q " + c.args, dir);
  EXPECT_EQ(run.exit_code, c.exit_code) << run.err;
  EXPECT_NE(run.err.find(c.message), std::string::npos) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_EQ(run.err.rfind("ndtom-map: ", 0), 0u) << run.err;
  EXPECT_TRUE(outputsOf(dir, "out").empty()) << "left " << outputsOf(dir, "out").front();
}

}  // namespace

TEST(MapperErrors, MissingUnknownOrDamagedInput) {
  TempDir dir;
  expectFailure(dir, (dir / "none.rawlog").string(), {"", 2, "none.rawlog: no such file"});
  writeText(dir / "notes.txt", "hello\n");
  expectFailure(dir, (dir / "notes.txt").string(), {"", 2, "unknown input format"});
  expectFailure(dir, (dir / "notes.txt").string(), {"--format lidar", 2, "--format"});
  writeText(dir / "noise.rawlog", std::string(4000, '\x5a'));
  expectFailure(dir, (dir / "noise.rawlog").string(), {"", 1, "noise.rawlog: entry 1"});
  // The first 100 kB of the (gzip) rawlog: the log ends inside an entry.
  writeText(dir / "cut.rawlog", readText(kSenaRawlog).substr(0, 100000));
  expectFailure(dir, (dir / "cut.rawlog").string(), {"", 1, "damaged or truncated"});
  writeText(dir / "empty.simplemap", "");
  expectFailure(dir, (dir / "empty.simplemap").string(), {"", 1, "not a readable CSimpleMap"});
}

TEST(MapperErrors, PosesThatDoNotMatchTheScans) {
  TempDir dir;
  copyLidarScans(dir / "scans");
  const std::string poses = readText(kLidar + "/poses.txt");
  writeText(dir / "scans/poses.txt", poses.substr(0, poses.find('\n') + 1));
  expectFailure(dir, (dir / "scans").string(), {"", 1, "poses.txt: 1 poses for 10 .pcd files"});
  fs::remove(dir / "scans/poses.txt");
  expectFailure(dir, (dir / "scans").string(), {"", 1, "no pose file"});
  // A rawlog's 225 scans and a 10-line KITTI file; a TUM file far from the scans' times.
  expectFailure(dir, kSenaRawlog,
                {"--poses " + quoted(kLidar + "/poses.txt"), 1, "10 poses for 225 scans"});
  writeText(dir / "tum.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n");
  expectFailure(dir, kSenaRawlog,
                {"--poses " + quoted((dir / "tum.txt").string()), 1, "no pose within 0.02 s"});
}

TEST(MapperErrors, BadPcdFailsEvenAfterScansWereMapped) {
  TempDir dir;
  copyLidarScans(dir / "scans");
  fs::copy_file(kLidar + "/poses.txt", dir / "scans/poses.txt");
  // Scan 5 lacks the x field: scans 0-4 are mapped before it is read.
  writeText(dir / "scans/full5.pcd",
            "VERSION 0.7\nFIELDS a y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\n"
            "HEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n");
  expectFailure(dir, (dir / "scans").string(), {"", 1, "full5.pcd: missing field 'x'"});
  // Damaged data: the file ends before its points.
  const std::string whole = readText(kLidar + "/full5.pcd");
  writeText(dir / "scans/full5.pcd", whole.substr(0, whole.size() / 2));
  expectFailure(dir, (dir / "scans").string(), {"", 1, "full5.pcd"});
}

TEST(MapperErrors, BadOptionValues) {
  TempDir dir;
  const std::string tum = kTum;
  expectFailure(dir, tum, {"--resolution abc", 2, "--resolution: not a number: 'abc'"});
  expectFailure(dir, tum, {"--p-hit 2", 2, "p_hit = 2"});
  expectFailure(dir, tum, {"--max-range 1 --min-range 2", 2, "max_range"});
  expectFailure(dir, tum, {"--ray-mode fast", 2, "--ray-mode"});
  expectFailure(dir, tum, {"--decimation 0", 2, "--decimation"});
  expectFailure(dir, tum, {"--threads 0", 2, "--threads"});
  expectFailure(dir, tum, {"--passes", 2, "--passes: missing value"});
  expectFailure(dir, tum, {"--coarse 1", 2, "--coarse"});
  expectFailure(dir, tum, {"--fx -5", 2, "--fx"});
  expectFailure(dir, tum, {"--bogus 1", 2, "--bogus: unknown option"});
  expectFailure(dir, tum, {"--poses x.txt", 2, "--poses: not used for TUM"});
  expectFailure(dir, tum, {"--config " + quoted((dir / "none.ini").string()), 2, "none.ini"});
  const std::string section = "[MetricMap_ndtOccupancyMap_00_insertOpts]\n";
  writeText(dir / "a.ini", section + "resolution = 0.3x\n");
  expectFailure(dir, tum,
                {"--config " + quoted((dir / "a.ini").string()), 2,
                 "a.ini: [MetricMap_ndtOccupancyMap_00_insertOpts] resolution: not a"});
  writeText(dir / "b.ini", section + "resolutoin = 0.3\n");
  expectFailure(dir, tum,
                {"--config " + quoted((dir / "b.ini").string()), 2, "unknown key 'resolutoin'"});
  writeText(dir / "c.ini", section + "p_miss = 0.7\n");
  expectFailure(dir, tum, {"--config " + quoted((dir / "c.ini").string()), 2, "p_miss = 0.7"});
  expectFailure(dir, tum,
                {"--config " + quoted((dir / "c.ini").string()) + " --section Other", 2,
                 "no section [Other]"});
}

TEST(MapperErrors, UsageMistakes) {
  TempDir dir;
  ProgramRun run = runMapper(quoted(kTum), dir);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("missing -o PREFIX"), std::string::npos) << run.err;
  run = runMapper(quoted(kTum) + " " + quoted(kLidar) + " -o x", dir);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("more than one INPUT"), std::string::npos) << run.err;
  writeText(dir / "file", "");
  run = runMapper(quoted(kTum) + " -o " + quoted((dir / "file/out").string()), dir);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("cannot create the folder"), std::string::npos) << run.err;
  run = runMapper("--help", dir);
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_NE(run.out.find("Usage: ndtom-map INPUT -o PREFIX"), std::string::npos);
  EXPECT_NE(run.out.find("--p-hit"), std::string::npos);
}

// Issue #17, class 7: a missing --poses file is a bad option value (it exited 1); --coarse is
// checked with --resolution before mapping (it failed after, naming the coarse resolution);
// FIFOs and devices are refused, where a FIFO named scan.pcd hung the run and /dev/zero as a
// poses file was read for 2 GB.
TEST(MapperErrors, HostileFilesAndOptionCombinations) {
  TempDir dir;
  copyLidarScans(dir / "scans");
  fs::copy_file(kLidar + "/poses.txt", dir / "scans/poses.txt");
  const std::string scans = (dir / "scans").string();
  expectFailure(dir, scans,
                {"--poses /nonexistent/poses.txt", 2, "--poses /nonexistent/poses.txt"});
  expectFailure(dir, scans, {"--poses /dev/zero", 2, "--poses /dev/zero: a device"});
  expectFailure(dir, kTum,
                {"--resolution 600 --coarse 2", 2, "--coarse 2: the coarse map's cells"});
  expectFailure(dir, kTum, {"--config /dev/zero", 2, "--config /dev/zero: a device"});
  expectFailure(dir, "/dev/zero", {"--format rawlog", 2, "INPUT /dev/zero: a device"});
  {
    const ndtom::testing::Fifo fifo((dir / "scans/full5.pcd").string(), 5.0);
    expectFailure(dir, scans, {"", 1, "full5.pcd: a FIFO, not a regular file"});
  }
  const ndtom::testing::Fifo log((dir / "fifo.rawlog").string(), 5.0);
  expectFailure(dir, log.path(), {"", 2, "fifo.rawlog: a FIFO"});
}

// Issue #17, class 2: a scan that would take the map over the memory budget stops the run
// before its blocks are allocated, naming the scan, the input, the option and the numbers
// (at --resolution 0.001 one TUM frame took over 4 GB).
TEST(MapperErrors, ScanOverTheMemoryBudget) {
  TempDir dir;
  expectFailure(
      dir, kTum,
      {"--resolution 0.001 --max-scans 1", 1,
       "depth/1311877813.991479.png in " + kTum + ": insertScan: a scan whose hits lie in"});
  expectFailure(dir, kTum,
                {"--resolution 0.001 --max-scans 1 --memory-budget 300", 1,
                 "over the memory budget of 300.0 MB (--memory-budget, in MB)"});
  expectFailure(dir, kTum, {"--memory-budget 0.5", 2, "memory_budget = 0.5"});
}

// Issue #17, class 6: a rerun that cannot replace one output (here a folder now stands in its
// place) leaves every previous output as it was. Before, it failed with three outputs new
// and two old.
TEST(MapperErrors, OutputsAreReplacedAllOrNone) {
  TempDir dir;
  const std::string prefix = (dir / "out").string();
  ProgramRun run = runMapper(quoted(kTum) + " -q --max-scans 3 -o " + quoted(prefix), dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::vector<std::string> names = outputsOf(dir, "out");
  ASSERT_EQ(names.size(), 6u);
  std::map<std::string, std::string> before;
  for (const auto& n : names) before[n] = readText(dir / n);
  fs::remove(dir / "out.3d.png");
  fs::create_directories(dir / "out.3d.png");
  run = runMapper(quoted(kTum) + " -q --max-scans 5 -o " + quoted(prefix), dir);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("cannot replace " + prefix + ".3d.png: a folder"), std::string::npos)
      << run.err;
  for (const auto& [name, bytes] : before) {
    if (name == "out.3d.png") continue;
    EXPECT_TRUE(sameBytes(readText(dir / name), bytes)) << name;
  }
  EXPECT_EQ(outputsOf(dir, "out").size(), 6u) << "no temporary left";
}
