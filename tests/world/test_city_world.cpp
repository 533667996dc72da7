// The city generator against brute force: rays cast through the 2D grid of boxes hit what a
// test of every box finds; the drive stays on the streets; scans lie on the surfaces; the
// program writes the same files for any thread count. Runs over the memory budget, the scan
// limit or the disk's free space are refused before anything is written (issue #38), and a
// run that fails leaves no scan behind.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>

#include "city_route.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_io/pcd_reader.h"
#include "simulated_lidar.h"
#include "world_options.h"

namespace ndtom::world {
namespace {

namespace fs = std::filesystem;

// The first surface along the ray by testing the ground and every box.
std::optional<double> bruteForceRay(const CityWorld& city, const Eigen::Vector3d& o,
                                    const Eigen::Vector3d& d, double max_range) {
  std::optional<double> best;
  if (d.z() < 0 && o.z() >= 0 && -o.z() / d.z() <= max_range) best = -o.z() / d.z();
  for (const Box& b : city.boxes())
    if (const auto t = rayBoxEntry(o, d.cwiseInverse(), b, max_range))
      if (!best || *t < *best) best = t;
  return best;
}

// Distance from p to the nearest surface (ground or box face).
double distanceToSurface(const CityWorld& city, const Eigen::Vector3d& p) {
  double best = std::abs(p.z());
  for (const Box& b : city.boxes()) {
    const Eigen::Vector3d outside = (b.lo - p).cwiseMax(Eigen::Vector3d::Zero()).cwiseMax(p - b.hi);
    const double d = outside.norm() > 0
                         ? outside.norm()
                         : std::min((p - b.lo).minCoeff(), (b.hi - p).minCoeff());  // inside
    best = std::min(best, d);
  }
  return best;
}

CityLayout smallCity(uint64_t seed = 1) {
  CityLayout l;
  l.blocks_x = 3;
  l.blocks_y = 2;
  l.seed = seed;
  return l;
}

TEST(CityWorld, RaysHitWhatEveryBoxTestedFinds) {
  const CityWorld city(smallCity());
  ASSERT_GT(city.boxes().size(), 50u);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1), along(0, 1);
  size_t hits = 0;
  for (int i = 0; i < 3000; ++i) {
    // From a street (between blocks) or anywhere over the city, in any direction.
    const Eigen::Vector3d o(along(rng) * 3 * 80 + (i % 2 ? 0 : -40), (rng() % 3) * 80.0 + u(rng),
                            1 + 5 * along(rng));
    Eigen::Vector3d d(u(rng), u(rng), 0.6 * u(rng));
    if (i % 50 == 0) d = Eigen::Vector3d(1, 0, 0);  // along a grid line: parallel slabs
    d.normalize();
    const auto grid = city.castRay(o, d, 120), brute = bruteForceRay(city, o, d, 120);
    ASSERT_EQ(grid.has_value(), brute.has_value()) << i;
    if (grid) {
      EXPECT_NEAR(*grid, *brute, 1e-9) << i;
      ++hits;
    }
  }
  EXPECT_GT(hits, 1500u);
}

TEST(CityWorld, SameSeedSameCity) {
  const CityWorld a(smallCity(4)), b(smallCity(4)), c(smallCity(5));
  ASSERT_EQ(a.boxes().size(), b.boxes().size());
  for (size_t i = 0; i < a.boxes().size(); ++i) {
    EXPECT_EQ(a.boxes()[i].lo, b.boxes()[i].lo);
    EXPECT_EQ(a.boxes()[i].hi, b.boxes()[i].hi);
  }
  EXPECT_FALSE(a.boxes().size() == c.boxes().size() && a.boxes()[0].hi == c.boxes()[0].hi);
  CityLayout bad = smallCity();
  bad.block_pitch = 25;
  EXPECT_THROW(CityWorld{bad}, std::invalid_argument);
}

TEST(CityRoute, DrivesOnTheStreetsStepByStepThroughNewStreets) {
  RouteSettings r;
  r.length = 3000;
  r.step = 2;
  CityLayout l;
  l.blocks_x = l.blocks_y = blocksForRoute(r.length, l.block_pitch);
  const CityWorld city(l);
  const auto poses = driveThrough(city, r);
  ASSERT_EQ(poses.size(), size_t(r.length / r.step) + 1);
  std::set<std::pair<long, long>> streets_seen;
  for (size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Vector3d p = poses[i].translation();
    EXPECT_FALSE(city.isInside(p)) << i;
    EXPECT_NEAR(p.z(), r.sensor_height, 1e-12);
    // On a street's centre line (x or y a multiple of the pitch), or in a corner's quarter
    // circle of 8 m, which stays within 8 (1 - 1/√2) = 2.34 m of the crossing's centre lines.
    const double fx = std::remainder(p.x(), l.block_pitch),
                 fy = std::remainder(p.y(), l.block_pitch);
    const bool on_line = std::abs(fx) < 1e-6 || std::abs(fy) < 1e-6;
    const bool in_corner =
        std::abs(fx) <= 8 && std::abs(fy) <= 8 && std::min(std::abs(fx), std::abs(fy)) <= 2.35;
    EXPECT_TRUE(on_line || in_corner) << i << ": " << p.transpose();
    if (i > 0) {
      EXPECT_LE((p - poses[i - 1].translation()).norm(), r.step + 1e-6) << i;
      EXPECT_GT((p - poses[i - 1].translation()).norm(), 0.8 * r.step) << i;
      // Facing the way it drives: on a corner's arc the chord is off the tangent by a
      // quarter of the step's turn (step / 8 m radians at most).
      const Eigen::Vector3d travel = p - poses[i - 1].translation();
      EXPECT_GT((poses[i - 1].linear() * Eigen::Vector3d::UnitX()).dot(travel.normalized()),
                std::cos(r.step / 8))
          << i;
      // The heading turns smoothly: at most step / 8 m radians a step.
      EXPECT_GT((poses[i - 1].linear() * Eigen::Vector3d::UnitX())
                    .dot(poses[i].linear() * Eigen::Vector3d::UnitX()),
                std::cos(r.step / 8 + 1e-9))
          << i;
    }
    streets_seen.insert({std::lround(p.x() / 40), std::lround(p.y() / 40)});
  }
  // Mostly new streets: half-segments visited against those driven.
  EXPECT_GT(double(streets_seen.size()), 0.7 * r.length / 40);
  EXPECT_THROW(driveThrough(city, RouteSettings{0, 1, 1.8, 1}), std::invalid_argument);
}

// With a margin the drive is the one of the inner city (margin 0, 2·margin fewer blocks),
// moved by margin blocks: every street it drives has city on every side.
TEST(CityRoute, MarginKeepsTheDriveOnTheInnerStreets) {
  RouteSettings r;
  r.length = 3000;
  r.step = 3;
  CityLayout inner;
  inner.blocks_x = inner.blocks_y = blocksForRoute(r.length, inner.block_pitch);
  const auto expected = driveThrough(CityWorld(inner), r);
  for (const int margin : {1, 2}) {
    CityLayout l = inner;
    l.blocks_x = l.blocks_y = inner.blocks_x + 2 * margin;
    r.margin = margin;
    const auto poses = driveThrough(CityWorld(l), r);
    ASSERT_EQ(poses.size(), expected.size());
    const double shift = margin * l.block_pitch, far = (l.blocks_x - margin) * l.block_pitch;
    for (size_t i = 0; i < poses.size(); ++i) {
      const Eigen::Vector3d p = poses[i].translation();
      EXPECT_LT((p - expected[i].translation() - Eigen::Vector3d(shift, shift, 0)).norm(), 1e-9)
          << margin << " " << i;
      EXPECT_LT((poses[i].linear() - expected[i].linear()).norm(), 1e-12) << margin << " " << i;
      EXPECT_TRUE(p.x() >= shift - 1e-9 && p.y() >= shift - 1e-9 && p.x() <= far + 1e-9 &&
                  p.y() <= far + 1e-9)
          << margin << " " << i << ": " << p.transpose();
    }
  }
  CityLayout small = inner;
  small.blocks_x = small.blocks_y = 2;
  r.margin = 1;
  EXPECT_THROW(driveThrough(CityWorld(small), r), std::invalid_argument);
  r.margin = -1;
  EXPECT_THROW(driveThrough(CityWorld(inner), r), std::invalid_argument);
}

TEST(WorldOptions, MarginAddsItsBlocksToTheCity) {
  const char* with_margin[] = {"ndtom-worldgen", "out", "--km", "3", "--margin", "2"};
  const WorldOptions o = parseWorldOptions(6, with_margin);
  EXPECT_EQ(o.route.margin, 2);
  EXPECT_EQ(o.city.blocks_x, blocksForRoute(3000, o.city.block_pitch) + 4);
  EXPECT_EQ(o.city.blocks_y, o.city.blocks_x);
  const char* too_small[] = {"ndtom-worldgen", "out", "--blocks", "2", "--margin", "1"};
  EXPECT_ANY_THROW(parseWorldOptions(6, too_small));
  const char* negative[] = {"ndtom-worldgen", "out", "--margin", "-1"};
  EXPECT_ANY_THROW(parseWorldOptions(4, negative));
  const char* huge[] = {"ndtom-worldgen", "out", "--margin", "101"};  // a city of over 200 blocks
  EXPECT_ANY_THROW(parseWorldOptions(4, huge));
}

TEST(SimulatedLidar, PointsLieOnTheSurfacesAndRepeatPerScanIndex) {
  const CityWorld city(smallCity());
  RouteSettings r;
  r.length = 100;
  r.step = 25;
  const auto poses = driveThrough(city, r);
  LidarModel lidar;
  lidar.rings = 8;
  lidar.azimuth_steps = 120;
  lidar.range_noise = 0;
  for (size_t i = 0; i < poses.size(); ++i) {
    const auto scan = simulateScan(city, lidar, poses[i], i);
    ASSERT_GT(scan.size(), 300u);
    for (size_t k = 0; k < scan.size(); k += 7) {
      const Eigen::Vector3d w = poses[i] * scan[k];
      EXPECT_LT(distanceToSurface(city, w), 1e-6) << i << "/" << k;
      EXPECT_LE(scan[k].norm(), lidar.max_range + 1e-9);
    }
  }
  lidar.range_noise = 0.05;
  const auto a = simulateScan(city, lidar, poses[1], 1), b = simulateScan(city, lidar, poses[1], 1),
             c = simulateScan(city, lidar, poses[1], 2);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  // Noise along the ray of about the σ asked for.
  double sum2 = 0;
  size_t n = 0;
  for (const auto& p : a) {
    const double range = p.norm();
    const auto exact = city.castRay(poses[1].translation(), poses[1].linear() * (p / range), 200);
    if (exact && range > 0) sum2 += (range - *exact) * (range - *exact), ++n;
  }
  ASSERT_GT(n, 300u);
  EXPECT_NEAR(std::sqrt(sum2 / double(n)), 0.05, 0.01);
}

std::string readAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(WorldgenProgram, SameFilesForAnyThreadCountAndReadableScans) {
  const fs::path dir = fs::temp_directory_path() / ("ndtom_worldgen_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string common = " --km 0.2 --step 10 --rings 8 --azimuth-steps 180 -q";
  for (const char* threads : {"1", "2"}) {
    const std::string cmd = std::string(NDTOM_WORLDGEN_EXE) + " " + (dir / threads).string() +
                            common + " --threads " + threads;
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  size_t scans = 0;
  for (const auto& e : fs::directory_iterator(dir / "1")) {
    const auto name = e.path().filename();
    EXPECT_EQ(readAll(e.path()), readAll(dir / "2" / name)) << name;
    scans += e.path().extension() == ".pcd";
  }
  EXPECT_EQ(scans, 21u);
  // poses.txt: one KITTI line per scan; the scans in the sensor frame land on the surfaces.
  std::ifstream poses(dir / "1" / "poses.txt");
  CityLayout l;
  l.blocks_x = l.blocks_y = blocksForRoute(200, l.block_pitch);
  const CityWorld city(l);
  std::string line;
  size_t lines = 0;
  while (std::getline(poses, line)) {
    std::istringstream in(line);
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) in >> m(r, c);
    char name[32];
    std::snprintf(name, sizeof name, "scan%06zu.pcd", lines);
    const auto cloud = ndtom::io::readPcd((dir / "1" / name).string());
    ASSERT_GT(cloud.points.size(), 100u);
    const Eigen::Isometry3d pose(m);
    double worst = 0;
    for (size_t k = 0; k < cloud.points.size(); k += 11)
      worst = std::max(worst, distanceToSurface(city, pose * cloud.points[k]));
    EXPECT_LT(worst, 0.02 * 6 + 1e-3) << name;  // 6σ of the default noise, float storage
    ++lines;
  }
  EXPECT_EQ(lines, scans);
  // --noise-seed: the same drive (poses) with other noise (every scan's points differ).
  const std::string other =
      std::string(NDTOM_WORLDGEN_EXE) + " " + (dir / "noise").string() + common + " --noise-seed 2";
  ASSERT_EQ(std::system(other.c_str()), 0) << other;
  EXPECT_EQ(readAll(dir / "noise" / "poses.txt"), readAll(dir / "1" / "poses.txt"));
  for (size_t i = 0; i < scans; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "scan%06zu.pcd", i);
    EXPECT_NE(readAll(dir / "noise" / name), readAll(dir / "1" / name)) << name;
  }
  // Bad options are usage errors (exit 2) naming the option.
  const std::string bad =
      std::string(NDTOM_WORLDGEN_EXE) + " " + (dir / "bad").string() + " --step 0 2>/dev/null";
  EXPECT_EQ(WEXITSTATUS(std::system(bad.c_str())), 2);
  fs::remove_all(dir);
}

// Runs ndtom-worldgen through sh with `args` (and any shell before it in `prefix`); the exit
// status, and stderr in `err`.
int runWorldgen(const std::string& args, std::string& err, const std::string& prefix = "") {
  const fs::path log =
      fs::temp_directory_path() / ("ndtom_worldgen_err_" + std::to_string(::getpid()));
  const std::string cmd = prefix + "'" + std::string(NDTOM_WORLDGEN_EXE) + "' " + args + " 2>'" +
                          log.string() + "' >/dev/null";
  const int status = std::system(("sh -c \"" + cmd + "\"").c_str());
  err = readAll(log);
  fs::remove(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Issue #38, class 1: what a run holds grows with its options (the city with --blocks or
// --km, each thread's scan with --rings x --azimuth-steps); over the memory budget it is
// refused by the option check, exit 2, naming the options and the figures, with nothing
// written. So are more than 10 million scans, and files that would not fit the disk.
TEST(WorldgenProgram, RunsOverTheLimitsAreRefusedUpFrontNamingTheOptions) {
  const fs::path dir =
      fs::temp_directory_path() / ("ndtom_worldgen_big_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string out = "'" + (dir / "out").string() + "'";
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {" --blocks 1000",
       {"--blocks 1000: a city of 1000x1000 blocks needs", "over the memory budget of"}},
      {" --blocks 400 --memory-budget 300",
       {"--blocks 400", "over the memory budget of 300.0 MB (--memory-budget, in MB)"}},
      {" --rings 512 --azimuth-steps 36000",
       {"--rings 512 x --azimuth-steps 36000 = 18.432 M rays a scan", "over the memory budget"}},
      {" --rings 64 --azimuth-steps 3600 --threads 8 --memory-budget 40",
       {"--rings 64 x --azimuth-steps 3600", "x --threads 8", "of 40.0 MB"}},
      {" --km 9000", {"--km 9000 (the city is sized for the drive): a city of 336x336 blocks"}},
      {" --km 10000 --step 1",
       {"--km 10000 / --step 1 = 10000001 scans: over the limit of 10000000"}},
      {" --km 20 --step 0.001", {"--km 20 / --step 0.001 = 20000001 scans: over the limit"}},
      // Within the limits and the budget, but ~1.5 TB of scans: refused before writing.
      {" --km 9000 --memory-budget 4000",
       {"--km 9000 / --step 1 = 9000001 scans", "of files, over the", "free on the disk of"}},
      {" --memory-budget 0.5", {"--memory-budget 0.5: must be at least 1 MB"}},
  };
  for (const auto& [args, messages] : cases) {
    std::string err;
    EXPECT_EQ(runWorldgen(out + args + " -q", err), 2) << args << ": " << err;
    for (const std::string& m : messages)
      EXPECT_NE(err.find(m), std::string::npos) << args << ": " << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << "one line: " << err;
    EXPECT_FALSE(fs::exists(dir / "out")) << args;
  }
  // The neighbours within the limits pass the option check: the same options with a larger
  // budget or fewer threads, 10 million scans exactly.
  const auto parses = [](std::vector<const char*> args) {
    args.insert(args.begin(), {"ndtom-worldgen", "out"});
    return parseWorldOptions(int(args.size()), args.data());
  };
  EXPECT_NO_THROW(parses(
      {"--rings", "512", "--azimuth-steps", "36000", "--threads", "2", "--memory-budget", "1500"}));
  EXPECT_NO_THROW(parses({"--blocks", "400", "--memory-budget", "1000"}));
  EXPECT_NO_THROW(parses({"--km", "9000", "--memory-budget", "1000"}));
  EXPECT_NO_THROW(parses({"--km", "9999.999", "--step", "1", "--memory-budget", "1000"}));
  EXPECT_NO_THROW(parses({"--km", "9.999", "--step", "0.001"}));
  // Without --threads, as many as the budget holds (one at least); with it, refused.
  const WorldOptions fewer =
      parses({"--rings", "64", "--azimuth-steps", "3600", "--memory-budget", "40"});
  EXPECT_GE(fewer.threads, 1);
  EXPECT_LE(double(runBytes(fewer)), 40e6);
  EXPECT_THROW(parses({"--rings", "64", "--azimuth-steps", "3600", "--memory-budget", "40",
                       "--threads", "8"}),
               ndtom::apps::UsageError);
  fs::remove_all(dir);
}

// The city's estimate bounds what it holds, so that the budget check holds.
TEST(CityWorld, EstimatedBytesBoundWhatTheCityHolds) {
  for (const int blocks : {1, 3, 16, 40})
    for (const uint64_t seed : {1u, 7u}) {
      CityLayout l;
      l.blocks_x = blocks;
      l.blocks_y = blocks + 1;
      l.seed = seed;
      const CityWorld city(l);
      EXPECT_GE(CityWorld::estimatedBytes(l), city.memoryBytes()) << blocks << " blocks";
      EXPECT_LE(CityWorld::estimatedBytes(l), 4 * city.memoryBytes()) << blocks << " blocks";
    }
}

// A run that fails once scans are written (here poses.txt: files are limited to 4-8 kB, and
// its 101 lines take ~20 kB, the scans under 1 kB each) leaves none in the folder, and
// nothing else of its own; the same run without the limit writes them all.
TEST(WorldgenProgram, AFailedRunLeavesNoScanBehind) {
  const fs::path dir =
      fs::temp_directory_path() / ("ndtom_worldgen_fail_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string args =
      "'" + dir.string() + "' --km 0.1 --step 1 --rings 2 --azimuth-steps 8 -q";
  std::string err;
  // SIGXFSZ ignored: a write past the limit fails with EFBIG instead of killing the program.
  EXPECT_EQ(runWorldgen(args, err, "trap '' XFSZ; ulimit -f 8; "), 1) << err;
  EXPECT_NE(err.find("cannot write " + (dir / "poses.txt").string()), std::string::npos) << err;
  ASSERT_TRUE(fs::is_directory(dir));
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir)) left.push_back(e.path().filename().string());
  EXPECT_TRUE(left.empty()) << left.size() << " files left, the first " << left.front();
  EXPECT_EQ(runWorldgen(args, err), 0) << err;
  size_t scans = 0;
  for (const auto& e : fs::directory_iterator(dir)) scans += e.path().extension() == ".pcd";
  EXPECT_EQ(scans, 101u);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ndtom::world
