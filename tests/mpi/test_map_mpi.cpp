// ndtom-map-mpi on the shipped lidar scans: its map files are ndtom-map's byte for byte for
// 1, 2 and 4 processes (more processes than cores: --oversubscribe), for either way of sharing
// the scans, either way of sharing the rays and either ray mode; the processes' parts are disjoint
// and cover the map; a bad command line is refused once, by every process, without hanging; a
// scan over the memory budget is named, as ndtom-map names it.
#include <cstdlib>

#include "mapper/mapper_run.h"

using namespace mapper_test;

namespace {

const std::string kMpiMapper = NDTOM_MAP_MPI_EXE;

ProgramRun runMpi(int processes, const std::string& args, const TempDir& dir) {
  // mpirun refuses root unless told; CI containers run as root.
  setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
  // Under AddressSanitizer, no leak check for these processes: Open MPI unloads its plugins
  // before exit, so their allocations cannot be named (or suppressed) in a report.
  const char* asan = std::getenv("ASAN_OPTIONS");
  const std::string asan_options = std::string(asan ? asan : "") + ":detect_leaks=0";
  return runExecutable("env",
                       quoted("ASAN_OPTIONS=" + asan_options) + " timeout 120 " + quoted(MPIEXEC) +
                           " -np " + std::to_string(processes) + " " + quoted(kMpiMapper) + " " +
                           args,
                       dir);
}

const std::string kMapOptions = " --resolution 0.2 --max-range 30 --no-pictures --quiet";

}  // namespace

TEST(MapMpi, MapFilesAreNdtomMapsForOneTwoAndFourProcesses) {
  TempDir dir;
  for (const std::string mode : {"PerPoint", "PerHitCell"}) {
    SCOPED_TRACE(mode);
    const std::string options = kMapOptions + " --ray-mode " + mode + " --tiles 2";
    const ProgramRun serial =
        runMapper(quoted(kLidar) + " -o " + quoted((dir / "serial").string()) + options, dir);
    ASSERT_EQ(serial.exit_code, 0) << serial.err;
    for (const int processes : {1, 2, 4}) {
      for (const std::string input : {"each", "broadcast"}) {
        for (const std::string share : {"tiles", "rays"}) {
          if (processes == 1 && input == "broadcast") continue;
          SCOPED_TRACE(std::to_string(processes) + " processes, scan input " + input +
                       ", rays shared by " + share);
          const std::string prefix = "np" + std::to_string(processes) + input + share;
          const ProgramRun run =
              runMpi(processes,
                     quoted(kLidar) + " -o " + quoted((dir / prefix).string()) + options +
                         " --scan-input " + input + " --rank-tiles 1 --ray-share " + share,
                     dir);
          ASSERT_EQ(run.exit_code, 0) << run.err;
          for (const std::string suffix : {".ndtom", ".ndtommap", ".ndtomtiles"})
            EXPECT_TRUE(
                sameBytes(readText(dir / ("serial" + suffix)), readText(dir / (prefix + suffix))))
                << suffix;

          // The parts are disjoint and together the map: their cells add up to the map's.
          const std::string json = readText(dir / (prefix + ".mpi.json"));
          EXPECT_EQ(jsonNumber(json, "ranks"), processes);
          double cells = 0;
          size_t at = 0, parts = 0;
          while ((at = json.find("\"cells\":", at)) != std::string::npos)
            cells += std::strtod(json.c_str() + (at += 8), nullptr), ++parts;
          EXPECT_EQ(parts, size_t(processes));
          const double map_cells =
              jsonNumber(readText(dir / "serial.summary.json"), "cells", "map");
          EXPECT_EQ(cells, map_cells);
          // Broadcast sends each scan's points once (24 bytes a point) and little else.
          const double sent = jsonNumber(json, "bytes_broadcast");
          if (input == "broadcast") {
            const double points = jsonNumber(readText(dir / "serial.summary.json"), "in", "points");
            EXPECT_GE(sent, 24 * points);
            EXPECT_LT(sent, 24 * points + 1000 * 10);
          } else {
            EXPECT_EQ(sent, 0);
          }
          // Sharing the rays, processes send each other counts; sharing the tiles, none.
          double exchanged = 0;
          for (at = 0; (at = json.find("\"bytes_exchanged\":", at)) != std::string::npos;)
            exchanged += std::strtod(json.c_str() + (at += 18), nullptr);
          if (share == "rays" && processes > 1) {
            EXPECT_GT(exchanged, 0);
          } else {
            EXPECT_EQ(exchanged, 0);
          }
        }
      }
    }
  }
}

TEST(MapMpi, BadCommandLinesAreRefusedByEveryProcessWithoutHanging) {
  TempDir dir;
  const std::string out = " -o " + quoted((dir / "m").string());
  for (const std::string bad : {" --rank-tiles 0", " --scan-input smoke", " --ray-share all",
                                " --passes 2", " --resolution -1", " --resident-budget 10"}) {
    SCOPED_TRACE(bad);
    const ProgramRun run = runMpi(2, quoted(kLidar) + out + bad, dir);
    EXPECT_NE(run.exit_code, 0);
    EXPECT_NE(run.exit_code, 124) << "timed out";
    // One message, from process 0.
    const size_t first = run.err.find("ndtom-map-mpi: ");
    ASSERT_NE(first, std::string::npos) << run.err;
    EXPECT_EQ(run.err.find("ndtom-map-mpi: ", first + 1), std::string::npos) << run.err;
  }
  const ProgramRun missing = runMpi(2, quoted((dir / "nothing").string()) + out, dir);
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.exit_code, 124) << "timed out";
  EXPECT_NE(missing.err.find("nothing"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(dir / "m.ndtom"));
}

// Issue #38, class 6: a scan that takes a process's part of the map over the memory budget
// stops the run (exit 1) with a message naming the scan (its index and file), the input and
// the option, as ndtom-map's does; whichever process hits it, and however the scans are shared.
TEST(MapMpi, AScanOverTheMemoryBudgetIsNamed) {
  TempDir dir;
  // 7 MB holds a scan's points but no process's part of the first scan's cells (with 16
  // MB, one of two processes' parts fitted at times: the rays are shared out by timing).
  const std::string args =
      quoted(kLidar) + " -o " + quoted((dir / "m").string()) + kMapOptions + " --memory-budget 7";
  for (const auto& [processes, input] :
       {std::pair<int, std::string>{1, "each"}, {2, "broadcast"}}) {
    SCOPED_TRACE(std::to_string(processes) + " processes, scan input " + input);
    const ProgramRun run = runMpi(processes, args + " --scan-input " + input, dir);
    EXPECT_EQ(run.exit_code, 1) << run.err;
    EXPECT_NE(run.err.find("over the memory budget of 7."), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(" MB (--memory-budget, in MB)"), std::string::npos) << run.err;
    bool named = false;
    for (int i = 0; i < 10; ++i)
      named = named || run.err.find("scan " + std::to_string(i) + " (full" + std::to_string(i) +
                                    ".pcd) in " + kLidar + ": ") != std::string::npos;
    EXPECT_TRUE(named) << run.err;
    // Every process's message names the scan (one that stopped as another failed, too).
    for (size_t at = 0; (at = run.err.find("ndtom-map-mpi: ", at)) != std::string::npos; ++at)
      EXPECT_EQ(run.err.compare(at + 15, 5, "scan "), 0) << run.err.substr(at, 200);
    EXPECT_FALSE(fs::exists(dir / "m.ndtom"));
  }
  // With a budget that holds the map, the same run writes it.
  const ProgramRun run = runMpi(2,
                                quoted(kLidar) + " -o " + quoted((dir / "m").string()) +
                                    kMapOptions + " --memory-budget 200 --scan-input broadcast",
                                dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(fs::exists(dir / "m.ndtom"));
}
