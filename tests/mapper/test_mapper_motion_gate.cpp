// ndtom-map --min-travel / --min-turn (the paper's insertion rule): the number of scans the
// program inserts equals a count made here from poses.txt with its own arithmetic.
#include <cmath>
#include <fstream>
#include <sstream>

#include "mapper_run.h"

using namespace mapper_test;

namespace {

struct Pose {
  double r[9], t[3];
};

std::vector<Pose> readKitti(const std::string& path) {
  std::vector<Pose> poses;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    double m[12];
    int n = 0;
    while (n < 12 && s >> m[n]) ++n;
    if (n != 12) continue;
    Pose p;
    for (int row = 0; row < 3; ++row) {
      for (int col = 0; col < 3; ++col) p.r[3 * row + col] = m[4 * row + col];
      p.t[row] = m[4 * row + 3];
    }
    poses.push_back(p);
  }
  return poses;
}

// Scans kept: the first, then each one at least `travel` m from, or `turn` degrees (angle
// of Ra^T Rb, from its trace) off, the last kept one. 0 disables a threshold.
size_t expectedKept(const std::vector<Pose>& poses, double travel, double turn) {
  size_t kept = 0;
  const Pose* last = nullptr;
  for (const Pose& p : poses) {
    bool keep = last == nullptr;
    if (!keep) {
      const double dx = p.t[0] - last->t[0], dy = p.t[1] - last->t[1], dz = p.t[2] - last->t[2];
      double trace = 0;  // trace(Ra^T Rb) = sum of the element-wise products
      for (int i = 0; i < 9; ++i) trace += last->r[i] * p.r[i];
      const double angle = std::acos(std::max(-1.0, std::min(1.0, (trace - 1) / 2))) * 180 / M_PI;
      keep = (travel > 0 && std::sqrt(dx * dx + dy * dy + dz * dz) >= travel) ||
             (turn > 0 && angle >= turn);
    }
    if (keep) {
      ++kept;
      last = &p;
    }
  }
  return kept;
}

size_t insertedScans(const std::string& folder, const std::string& options, const TempDir& dir) {
  const ProgramRun run = runMapper(quoted(folder) + " -o " + quoted((dir / "m").string()) +
                                       " --no-pictures --quiet --resolution 0.5 " + options,
                                   dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  const double n = jsonNumber(readText(dir / "m.summary.json"), "scans_inserted");
  EXPECT_FALSE(std::isnan(n)) << "no scans_inserted in the summary";
  return size_t(n);
}

}  // namespace

TEST(MapperMotionGate, KeptScansMatchAnIndependentCountOnTheShippedScans) {
  TempDir dir;
  const std::vector<Pose> poses = readKitti(kLidar + "/poses.txt");
  ASSERT_EQ(poses.size(), 10u);
  // The shipped scans barely move: small thresholds, so that some scans are kept and some not.
  const struct {
    double travel, turn;
  } cases[] = {{0.005, 0}, {0.01, 0}, {0, 0.1}, {0, 0.2}, {0.01, 0.2}};
  bool discriminating = false;
  for (const auto& c : cases) {
    std::ostringstream options;
    if (c.travel > 0) options << " --min-travel " << c.travel;
    if (c.turn > 0) options << " --min-turn " << c.turn;
    const size_t expected = expectedKept(poses, c.travel, c.turn);
    discriminating |= expected > 1 && expected < poses.size();
    EXPECT_EQ(insertedScans(kLidar, options.str(), dir), expected) << options.str();
  }
  EXPECT_TRUE(discriminating) << "every case keeps all scans or only the first";
  EXPECT_EQ(insertedScans(kLidar, "", dir), poses.size()) << "off by default";
}

// The paper's 0.05 m on the full sequence, when the shared data is beside the checkout.
TEST(MapperMotionGate, FullLidarSequenceAtFiveCentimetres) {
  const std::string full = std::string(NDTOM_SHARED_DATASETS) + "/balm-realworld";
  if (!fs::exists(full + "/poses.txt")) GTEST_SKIP() << "no " << full;
  TempDir dir;
  const std::vector<Pose> poses = readKitti(full + "/poses.txt");
  const size_t expected = expectedKept(poses, 0.05, 0);
  ASSERT_GT(expected, 1u);
  ASSERT_LT(expected, poses.size());
  EXPECT_EQ(insertedScans(full, "--min-travel 0.05 --resolution 1.0", dir), expected);
}

TEST(MapperMotionGate, BadThresholdsAreUsageErrors) {
  TempDir dir;
  for (const char* bad : {"--min-travel -0.1", "--min-travel 0", "--min-travel x", "--min-turn 200",
                          "--min-turn nan", "--min-turn"}) {
    const ProgramRun run = runMapper(
        quoted(kLidar) + " -o " + quoted((dir / "m").string()) + " --no-pictures " + bad, dir);
    EXPECT_EQ(run.exit_code, 2) << bad << ": " << run.err;
    EXPECT_NE(run.err.find(std::string(bad).substr(0, 10)), std::string::npos) << run.err;
  }
}
