// ndtom-map --resident-budget on a drive through the procedural city: the tiled map is the
// one the in-memory run writes, byte for byte, and the resident map stays within the budget
// plus the tiles one scan reaches (computed here from the scans and the in-memory map).
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>

#include "mapper_run.h"
#include "ndtom/files/map_io.h"
#include "ndtom/files/tiled_map_io.h"
#include "ndtom/scale/block_moves.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

namespace {

using namespace mapper_test;

constexpr int kTileBlocks = 2;    // 6.4 m tiles at 0.4 m
constexpr double kMaxRange = 30;  // the map's; the lidar sees 40 m
constexpr double kResolution = 0.4;

// Each scan's box: the origin and the points, each cut at max_range, and a cell of margin.
std::vector<Eigen::AlignedBox3d> scanBoxes(const fs::path& city) {
  const auto poses = ndtom::io::readPoseFile((city / "poses.txt").string());
  std::vector<Eigen::AlignedBox3d> boxes;
  for (size_t i = 0; i < poses.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "scan%06zu.pcd", i);
    const auto cloud = ndtom::io::readPcd((city / name).string());
    const Eigen::Vector3d origin = (poses[i].pose * cloud.viewpoint).translation();
    Eigen::AlignedBox3d box(origin);
    for (const Eigen::Vector3d& p : cloud.points) {
      const Eigen::Vector3d w = poses[i].pose * p;
      const double range = (w - origin).norm();
      if (std::isfinite(range))
        box.extend(origin + (w - origin) * std::min(1.0, kMaxRange / range));
    }
    box.min().array() -= kResolution;
    box.max().array() += kResolution;
    boxes.push_back(box);
  }
  return boxes;
}

// The memory of the map's tiles that meet any of `boxes`, lent out of the map and back.
size_t tilesBytes(ndtom::NdtMap& map, const std::vector<Eigen::AlignedBox3d>& boxes) {
  ndtom::NdtMap part = ndtom::extractBlocks(map, [&](const ndtom::CellIndex& block) {
    const auto tile =
        ndtom::tileBoxOf(ndtom::tileOfBlock(block, kTileBlocks), kTileBlocks, kResolution);
    return std::any_of(boxes.begin(), boxes.end(),
                       [&](const auto& b) { return tile.intersects(b); });
  });
  const size_t bytes = part.memoryBytes();
  ndtom::absorbBlocks(map, std::move(part));
  return bytes;
}

// The most the resident map may hold during any scan k: before it, the resident map is
// within the budget, or holds only scan k-1's tiles (all others spilled); scan k adds its own
// tiles. Measured on the final map, which holds at least what each tile held earlier.
size_t residentBound(ndtom::NdtMap& map, const std::vector<Eigen::AlignedBox3d>& boxes,
                     size_t budget, size_t* largest_window) {
  size_t bound = 0;
  *largest_window = 0;
  for (size_t k = 0; k < boxes.size(); ++k) {
    const size_t own = tilesBytes(map, {boxes[k]});
    const size_t both = k > 0 ? tilesBytes(map, {boxes[k - 1], boxes[k]}) : own;
    *largest_window = std::max(*largest_window, own);
    bound = std::max(bound, std::max(budget + own, both));
  }
  return bound;
}

TEST(MapperOutOfCore, TiledFileIsTheInMemoryOneAndMemoryStaysInBudget) {
  const TempDir dir;
  const fs::path city = dir / "city";
  const std::string worldgen = std::string(NDTOM_WORLDGEN_EXE) + " " + quoted(city.string()) +
                               " --km 0.5 --step 5 --blocks 3 --rings 12 --azimuth-steps 360 "
                               "--max-range 40 -q";
  ASSERT_EQ(std::system(worldgen.c_str()), 0);
  const std::string common = quoted(city.string()) + " --resolution 0.4 --max-range 30 --tiles " +
                             std::to_string(kTileBlocks) + " -q ";

  ProgramRun run = runMapper(common + "--no-pictures -o " + quoted((dir / "mem").string()), dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const double map_bytes = jsonNumber(readText(dir / "mem.summary.json"), "map_bytes", "map");
  const double budget_mb = map_bytes / 10 / 1e6;
  char budget[32];
  std::snprintf(budget, sizeof budget, "%.6f", budget_mb);

  fs::create_directories(dir / "ooc");
  run = runMapper(
      common + "--resident-budget " + budget + " -o " + quoted((dir / "ooc" / "city").string()),
      dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(
      sameBytes(readText(dir / "ooc" / "city.ndtomtiles"), readText(dir / "mem.ndtomtiles")));
  // Only the tiles and the summary: the spill folder is gone.
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir / "ooc")) left.push_back(e.path().filename());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"city.ndtomtiles", "city.summary.json"}));

  const std::string json = readText(dir / "ooc" / "city.summary.json");
  const double spills = jsonNumber(json, "spills"), loads = jsonNumber(json, "loads");
  const double peak = jsonNumber(json, "peak_resident_bytes");
  const double budget_bytes = jsonNumber(json, "resident_budget_bytes");
  EXPECT_NEAR(budget_bytes, map_bytes / 10, 1);
  EXPECT_GT(spills, 10);
  EXPECT_GT(loads, 0);  // the drive comes back to streets it has left
  EXPECT_GT(jsonNumber(json, "spilled_bytes"), 0);
  // The same map: its counts, added up tile by tile, are the in-memory run's.
  const std::string mem_json = readText(dir / "mem.summary.json");
  EXPECT_EQ(jsonNumber(json, "cells", "map"), jsonNumber(mem_json, "cells", "map"));
  EXPECT_EQ(jsonNumber(json, "occupied_cells", "map"),
            jsonNumber(mem_json, "occupied_cells", "map"));

  // The budget plus one scan's tiles (or two scans' tiles, where one scan's exceed the
  // budget); hash buckets (8 bytes, at most two a block) aside.
  ndtom::NdtMap map = ndtom::loadMap((dir / "mem.ndtom").string());
  size_t window = 0;
  size_t blocks = 0;
  map.forEachBlock([&](const ndtom::CellIndex&) { ++blocks; });
  const double bound =
      double(residentBound(map, scanBoxes(city), size_t(budget_bytes), &window)) + 16.0 * blocks;
  std::printf(
      "map %.0f B, budget %.0f B, largest scan window %zu B, peak resident %.0f B "
      "(bound %.0f B), %.0f spills, %.0f loads\n",
      map_bytes, budget_bytes, window, peak, bound, spills, loads);
  EXPECT_GT(peak, budget_bytes);  // else the budget was never put to the test
  EXPECT_LE(peak, bound);
}

TEST(MapperOutOfCore, BadValuesAreRefusedClearly) {
  const TempDir dir;
  const std::string out = " -o " + quoted((dir / "m").string());
  for (const char* bad : {"0", "-5", "abc", "1e-9", "nan"}) {
    const ProgramRun run =
        runMapper(quoted(kLidar) + out + " --resident-budget " + std::string(bad), dir);
    EXPECT_EQ(run.exit_code, 2) << bad;
    EXPECT_NE(run.err.find("--resident-budget"), std::string::npos) << run.err;
  }
  for (const char* clash : {"--coarse 2", "--octomap"}) {
    const ProgramRun run =
        runMapper(quoted(kLidar) + out + " --resident-budget 10 " + std::string(clash), dir);
    EXPECT_EQ(run.exit_code, 2) << clash;
    EXPECT_NE(run.err.find("needs the whole map in memory"), std::string::npos) << run.err;
  }
  const ProgramRun run = runMapper(quoted(kLidar) + out + " --spill-dir /tmp", dir);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("only with --resident-budget"), std::string::npos) << run.err;
  EXPECT_TRUE(outputsOf(dir, "m").empty());
}

// Issue #38, class 6: a --spill-dir that cannot hold the spill folder (a file, a path under
// a file, a read-only folder) is refused before the work starts, exit 2, with a message
// that names the option and the folder and says it is not writable (a read-only folder
// said "No such file or directory"). Root writes into read-only folders: as root that case
// is left out, and said so; the file cases fail for root too.
TEST(MapperOutOfCore, ASpillDirThatIsNotAWritableFolderIsRefusedNamingIt) {
  const TempDir dir;
  const std::string out = " -o " + quoted((dir / "m").string());
  const std::string common =
      quoted(kLidar) + out +
      " --resolution 0.4 --max-scans 2 --no-pictures -q --resident-budget 10";
  const fs::path file = dir / "a_file";
  std::ofstream(file) << "not a folder";
  std::vector<std::pair<fs::path, std::string>> cases = {
      {file, "not a writable folder (a file)"},
      {file / "sub",
       "not a writable folder (cannot create it: " + std::string(std::strerror(ENOTDIR))},
  };
  const fs::path read_only = dir / "read_only";
  fs::create_directories(read_only);
  ::chmod(read_only.c_str(), 0555);
  if (::geteuid() != 0)
    cases.push_back({read_only, "not a writable folder (cannot create the spill folder " +
                                    (read_only / "m.spill-").string()});
  else
    std::printf("as root: a read-only --spill-dir is writable, that case is left out\n");
  for (const auto& [spill, message] : cases) {
    SCOPED_TRACE(spill.string());
    const ProgramRun run = runMapper(common + " --spill-dir " + quoted(spill.string()), dir);
    EXPECT_EQ(run.exit_code, 2) << run.err;
    EXPECT_NE(run.err.find("--spill-dir " + spill.string() + ": " + message), std::string::npos)
        << run.err;
    EXPECT_EQ(run.err.find("No such file or directory"), std::string::npos) << run.err;
  }
  ::chmod(read_only.c_str(), 0755);
  EXPECT_TRUE(outputsOf(dir, "m").empty());
  // A folder that does not exist yet is created; the run writes its map and removes its
  // spill folder.
  const fs::path fresh = dir / "new" / "spill";
  const ProgramRun run = runMapper(common + " --spill-dir " + quoted(fresh.string()), dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(fs::exists(dir / "m.ndtomtiles"));
  EXPECT_TRUE(fs::is_directory(fresh));
  EXPECT_TRUE(fs::is_empty(fresh));
}

}  // namespace
