// ndtom-localize as a user runs it, on the lidar scans shipped with the tests: ndtom-map
// builds a map of scans 0-4, the program localizes scans 5-9 (a folder without poses.txt)
// from a start 0.5 m and 5° off; every scan must come within 5 cm and 0.5° of its reference
// pose (poses.txt, which the program never sees).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <iomanip>

#include "mapper/mapper_run.h"
#include "ndtom/files/map_io.h"
#include "ndtom/files/tiled_map_io.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"
#include "support/special_files.h"

using namespace mapper_test;

namespace {

const std::string kLocalize = NDTOM_LOCALIZE_EXE;

// scans 5-9 of the shipped subset with their times, no poses.
void copyScans(const TempDir& dir, const fs::path& folder) {
  fs::create_directories(folder);
  std::ifstream times(kLidar + "/times.txt");
  std::ofstream out((folder / "times.txt").string());
  std::string line;
  for (int i = 0; i < 10 && std::getline(times, line); ++i) {
    if (i < 5) continue;
    fs::copy_file(kLidar + "/full" + std::to_string(i) + ".pcd",
                  folder / ("full" + std::to_string(i) + ".pcd"));
    out << line << "\n";
  }
  (void)dir;
}

std::string tumPose(const Eigen::Isometry3d& p) {
  const Eigen::Quaterniond q(p.linear());
  std::ostringstream s;
  s << std::setprecision(12) << p.translation().x() << " " << p.translation().y() << " "
    << p.translation().z() << " " << q.x() << " " << q.y() << " " << q.z() << " " << q.w();
  return s.str();
}

struct Fixture {
  TempDir dir;
  std::vector<ndtom::io::StampedPose> reference = ndtom::io::readPoseFile(kLidar + "/poses.txt");
  std::vector<double> times;
  std::string map;
  fs::path scans;

  Fixture() {
    // The map: ndtom-map on scans 0-4 (with their poses).
    const ProgramRun mapped = runMapper(mapper_test::quoted(kLidar) +
                                            " --max-scans 5 --max-range 30 --no-pictures -q -o " +
                                            mapper_test::quoted((dir / "map").string()),
                                        dir);
    EXPECT_EQ(mapped.exit_code, 0) << mapped.err;
    map = (dir / "map.ndtom").string();
    scans = dir / "scans";
    copyScans(dir, scans);
    std::ifstream in(kLidar + "/times.txt");
    for (double t; in >> t;) times.push_back(t);
  }

  Eigen::Isometry3d offStart() const {
    Eigen::Isometry3d start = reference[5].pose;
    start.translation() += Eigen::Vector3d(0.4, -0.3, 0.0);
    start.linear() = Eigen::AngleAxisd(5 * M_PI / 180, Eigen::Vector3d::UnitZ()) * start.linear();
    return start;
  }
};

}  // namespace

TEST(LocalizeEndToEnd, TracksHeldOutScansToTheirReferencePoses) {
  Fixture f;
  for (const std::string& map : {f.map, (f.dir / "map.ndtommap").string()}) {
    for (const char* method : {"p2d", "d2d"}) {
      const std::string prefix = (f.dir / (std::string("loc-") + method)).string();
      const ProgramRun run =
          runExecutable(kLocalize,
                        mapper_test::quoted(map) + " " + mapper_test::quoted(f.scans.string()) +
                            " -o " + mapper_test::quoted(prefix) + " --threads 2 --method " +
                            method + " --initial " + mapper_test::quoted(tumPose(f.offStart())),
                        f.dir);
      ASSERT_EQ(run.exit_code, 0) << run.err;
      EXPECT_NE(run.out.find("localized 5 of 5 scans (0 lost)"), std::string::npos) << run.out;
      EXPECT_NE(run.err.find("PCD folder"), std::string::npos);
      const auto estimated = ndtom::io::readPoseFile(prefix + ".tum", ndtom::io::PoseFormat::Tum);
      ASSERT_EQ(estimated.size(), 5u);
      for (size_t k = 0; k < 5; ++k) {
        const Eigen::Isometry3d& truth = f.reference[5 + k].pose;
        const Eigen::Isometry3d error = truth.inverse() * estimated[k].pose;
        EXPECT_LT(error.translation().norm(), 0.05) << method << " scan " << 5 + k;
        EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle() * 180 / M_PI, 0.5) << method;
        EXPECT_NEAR(estimated[k].time, f.times[5 + k], 1e-6);  // from times.txt
      }
      const std::string json = readText(prefix + ".summary.json");
      EXPECT_EQ(jsonNumber(json, "scans"), 5);
      EXPECT_EQ(jsonNumber(json, "tracked") + jsonNumber(json, "recovered"), 5);
      EXPECT_EQ(jsonNumber(json, "resolution", "per_scan"), 3.2);  // the coarsest level first
      EXPECT_TRUE(fs::exists(prefix + ".top.png"));
      const std::string csv = readText(prefix + ".scans.csv");
      EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 6) << csv;  // header + 5 scans
      EXPECT_NE(csv.find("\n4,"), std::string::npos) << csv;          // the folder's last scan
    }
  }
}

TEST(LocalizeEndToEnd, ScansOutsideTheMapAreReportedNotTracked) {
  Fixture f;
  Eigen::Isometry3d far = f.offStart();
  far.translation() += Eigen::Vector3d(400, 0, 0);
  const std::string prefix = (f.dir / "far").string();
  const ProgramRun run =
      runExecutable(kLocalize,
                    mapper_test::quoted(f.map) + " " + mapper_test::quoted(f.scans.string()) +
                        " -o " + mapper_test::quoted(prefix) + " --no-pictures --initial " +
                        mapper_test::quoted(tumPose(far)),
                    f.dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("localized 0 of 5 scans (5 lost)"), std::string::npos) << run.out;
  const std::string json = readText(prefix + ".summary.json");
  EXPECT_EQ(jsonNumber(json, "lost"), 5);
  EXPECT_NE(json.find("\"failure\": \"only"), std::string::npos);
  EXPECT_NE(json.find("search around the prediction"), std::string::npos);
  EXPECT_EQ(readText(prefix + ".tum"), "");  // no pose is claimed
}

// The localized scans extend the prior map in a file of its own; the prior map's file is
// never written.
TEST(LocalizeEndToEnd, SaveMapWritesThePriorMapExtendedByTheLiveMap) {
  Fixture f;
  const std::string prior_bytes = readText(f.map);
  const std::string prefix = (f.dir / "run").string(), extended = (f.dir / "extended").string();
  const std::string common = mapper_test::quoted(f.map) + " " +
                             mapper_test::quoted(f.scans.string()) + " --no-pictures --initial " +
                             mapper_test::quoted(tumPose(f.offStart())) + " --save-map " +
                             mapper_test::quoted(extended) + " -o ";
  const ProgramRun run = runExecutable(kLocalize, common + mapper_test::quoted(prefix), f.dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(readText(f.map), prior_bytes);
  const ndtom::NdtMap prior = ndtom::loadMap(f.map);
  const ndtom::NdtMap bigger = ndtom::loadMap(extended + ".ndtom");
  EXPECT_GT(bigger.numCells(), prior.numCells());
  prior.forEachCell([&](const ndtom::CellView& c) {
    const auto e = bigger.cell(c.index);
    ASSERT_TRUE(e.has_value());
    EXPECT_EQ(e->logodds, c.logodds);
  });
  const std::string csv = readText(prefix + ".scans.csv");
  EXPECT_NE(csv.find("placed_in"), std::string::npos);
  // Without the live map there is nothing to save: refused before any work.
  const ProgramRun refused = runExecutable(
      kLocalize, common + mapper_test::quoted(prefix + "2") + " --live-map off", f.dir);
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("needs the live map"), std::string::npos) << refused.err;
}

TEST(LocalizeEndToEnd, WithoutAStartPoseTheFirstScanIsSearchedForAndErrorsReported) {
  Fixture f;
  // The reference for scans 5-9 (KITTI, line i = i-th scan of the folder).
  const std::string reference = (f.dir / "reference.txt").string();
  {
    std::ifstream in(kLidar + "/poses.txt");
    std::ofstream out(reference);
    std::string line;
    for (int i = 0; std::getline(in, line); ++i)
      if (i >= 5) out << line << "\n";
  }
  const std::string prefix = (f.dir / "global").string();
  const ProgramRun run = runExecutable(
      kLocalize,
      mapper_test::quoted(f.map) + " " + mapper_test::quoted(f.scans.string()) + " -o " +
          mapper_test::quoted(prefix) + " --reference " + mapper_test::quoted(reference),
      f.dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("localized 5 of 5 scans (0 lost)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("1 found by global search"), std::string::npos) << run.out;
  const std::string json = readText(prefix + ".summary.json");
  EXPECT_EQ(jsonNumber(json, "relocalized"), 1);
  EXPECT_EQ(jsonNumber(json, "scans", "accuracy"), 5);
  EXPECT_LT(jsonNumber(json, "ate_rmse_m"), 0.05);
  EXPECT_LT(jsonNumber(json, "rotation_max_deg"), 0.5);
  EXPECT_NE(json.find("\"found_by\": \"global search\""), std::string::npos);
}

// The input has its own poses (poses.txt beside the scans) and --reference gives others,
// 100 m away: the errors are against --reference, the one asked for.
TEST(LocalizeEndToEnd, ReferenceFileWinsOverTheInputsOwnPoses) {
  Fixture f;
  const std::string moved = (f.dir / "moved.txt").string();
  {
    std::ifstream in(kLidar + "/poses.txt");
    std::ofstream own(f.scans / "poses.txt"), out(moved);
    std::string line;
    for (int i = 0; std::getline(in, line); ++i) {
      if (i < 5 || i > 9) continue;
      own << line << "\n";
      std::istringstream fields(line);
      std::vector<double> v(12);
      for (double& x : v) fields >> x;
      v[3] += 100;  // x of the translation, KITTI row-major 3 x 4
      for (size_t k = 0; k < v.size(); ++k)
        out << std::setprecision(12) << v[k] << (k + 1 < v.size() ? " " : "\n");
    }
  }
  const std::string prefix = (f.dir / "moved").string();
  const ProgramRun run = runExecutable(
      kLocalize,
      mapper_test::quoted(f.map) + " " + mapper_test::quoted(f.scans.string()) + " -o " +
          mapper_test::quoted(prefix) + " --no-pictures --initial " +
          mapper_test::quoted(tumPose(f.offStart())) + " --reference " + mapper_test::quoted(moved),
      f.dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string json = readText(prefix + ".summary.json");
  EXPECT_EQ(jsonNumber(json, "scans", "accuracy"), 5);
  EXPECT_NEAR(jsonNumber(json, "ate_rmse_m"), 100, 0.05);
}

TEST(LocalizeEndToEnd, AKidnappedStartIsFoundAgainAfterLostScans) {
  Fixture f;
  Eigen::Isometry3d kidnapped = f.offStart();
  kidnapped.translation() += Eigen::Vector3d(25, -15, 0);  // far beyond the local search
  const std::string prefix = (f.dir / "kidnap").string();
  const ProgramRun run =
      runExecutable(kLocalize,
                    mapper_test::quoted(f.map) + " " + mapper_test::quoted(f.scans.string()) +
                        " -o " + mapper_test::quoted(prefix) + " --relocalize 1 --initial " +
                        mapper_test::quoted(tumPose(kidnapped)),
                    f.dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string json = readText(prefix + ".summary.json");
  EXPECT_EQ(jsonNumber(json, "lost"), 1);  // the first scan, from the wrong start
  EXPECT_EQ(jsonNumber(json, "relocalized"), 1);
  EXPECT_EQ(jsonNumber(json, "localized"), 4);
  const auto estimated = ndtom::io::readPoseFile(prefix + ".tum", ndtom::io::PoseFormat::Tum);
  ASSERT_EQ(estimated.size(), 4u);  // lost scans have no line
  for (size_t k = 0; k < 4; ++k)
    EXPECT_LT((estimated[k].pose.translation() - f.reference[6 + k].pose.translation()).norm(),
              0.05);
}

// Issue #38: a whole-map search can find a look-alike place (another city's street) that
// passes every check of one scan. Its pose stands only once the next scan tracks from it:
// followed by a scan of nowhere in the map (scan 6 lifted 40 m), or by no scan, the found
// pose is withdrawn, the scan lost, saying why; followed by scan 6 itself, it stands.
TEST(LocalizeEndToEnd, AGlobalSearchPoseStandsOnlyWhenTheNextScanConfirmsIt) {
  Fixture f;
  const auto points = [](int i) {
    std::vector<Eigen::Vector3d> p;
    for (const Eigen::Vector3d& q :
         ndtom::io::readPcd(kLidar + "/full" + std::to_string(i) + ".pcd").points)
      if (q.allFinite()) p.push_back(q);
    return p;
  };
  const auto run = [&](const std::string& name,
                       const std::vector<std::vector<Eigen::Vector3d>>& scans) {
    const fs::path folder = f.dir / name;
    fs::create_directories(folder);
    std::ofstream times((folder / "times.txt").string());
    for (size_t k = 0; k < scans.size(); ++k) {
      ndtom::io::writePcdBinary((folder / ("full" + std::to_string(k) + ".pcd")).string(),
                                scans[k]);
      times << std::setprecision(12) << f.times[5 + k] << "\n";
    }
    times.close();
    const std::string prefix = (f.dir / name).string() + "-out";
    const ProgramRun r =
        runExecutable(kLocalize,
                      mapper_test::quoted(f.map) + " " + mapper_test::quoted(folder.string()) +
                          " -o " + mapper_test::quoted(prefix) + " --no-pictures",
                      f.dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return readText(prefix + ".summary.json");
  };
  std::vector<Eigen::Vector3d> lifted = points(6);
  for (Eigen::Vector3d& p : lifted) p.z() += 40;
  const std::string nowhere = run("then-nowhere", {points(5), lifted});
  EXPECT_EQ(jsonNumber(nowhere, "relocalized"), 0);
  EXPECT_EQ(jsonNumber(nowhere, "lost"), 2);
  EXPECT_NE(nowhere.find("was not confirmed: the next scan could not be tracked from it"),
            std::string::npos)
      << nowhere;
  const std::string alone = run("alone", {points(5)});
  EXPECT_EQ(jsonNumber(alone, "lost"), 1);
  EXPECT_NE(alone.find("was not confirmed: no scan came after it"), std::string::npos) << alone;
  const std::string confirmed = run("confirmed", {points(5), points(6)});
  EXPECT_EQ(jsonNumber(confirmed, "relocalized"), 1);
  EXPECT_EQ(jsonNumber(confirmed, "localized"), 2);
}

TEST(LocalizeEndToEnd, BadCommandLinesAndInputsFailCleanly) {
  Fixture f;
  const std::string start = " --initial " + mapper_test::quoted(tumPose(f.offStart()));
  const std::string io =
      mapper_test::quoted(f.scans.string()) + " -o " + mapper_test::quoted((f.dir / "x").string());
  struct Case {
    std::string args;
    int exit_code;
    std::string message;
  };
  const std::vector<Case> cases = {
      {mapper_test::quoted(f.map) + " " + io + " --relocalize 0", 2, "--relocalize"},
      {mapper_test::quoted(f.map) + " " + io + " --reference-format xyz", 2, "--reference-format"},
      {mapper_test::quoted(f.map) + " " + io + " --reference " +
           mapper_test::quoted((f.dir / "no-such-poses.txt").string()),
       2, "no-such-poses.txt"},
      {mapper_test::quoted(f.map) + " " + io + " --initial '1 2 3'", 2, "expected 7 numbers"},
      {mapper_test::quoted(f.map) + " " + io + start + " --method icp", 2, "--method"},
      {mapper_test::quoted(f.map) + " " + io + start + " --levels 1,2", 2, "level_factors"},
      {mapper_test::quoted(f.map) + " " + io + start + " --threads 0", 2, "--threads"},
      {mapper_test::quoted((f.dir / "none.ndtom").string()) + " " + io + start, 1,
       "no such map file"},
      {mapper_test::quoted(kLidar + "/full0.pcd") + " " + io + start, 1, "not a readable NDT-OM"},
      {mapper_test::quoted(f.map) + " " + mapper_test::quoted((f.dir / "nothing").string()) +
           " -o x" + start,
       2, "nothing"},
  };
  for (const Case& c : cases) {
    const ProgramRun run = runExecutable(kLocalize, c.args, f.dir);
    EXPECT_EQ(run.exit_code, c.exit_code) << c.args << "\n" << run.err;
    EXPECT_NE(run.err.find(c.message), std::string::npos) << c.args << "\n" << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  }
  EXPECT_FALSE(fs::exists(f.dir / "x.tum"));

  // times.txt that is not a regular file: refused by name, not read (a FIFO would block).
  const fs::path fifo_scans = f.dir / "fifo-scans";
  fs::create_directories(fifo_scans);
  fs::copy_file(f.scans / "full5.pcd", fifo_scans / "full5.pcd");
  const ndtom::testing::Fifo times((fifo_scans / "times.txt").string(), 30);
  const ProgramRun run =
      runExecutable(kLocalize,
                    mapper_test::quoted(f.map) + " " + mapper_test::quoted(fifo_scans.string()) +
                        " -o " + mapper_test::quoted((f.dir / "y").string()) + start,
                    f.dir);
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find("times.txt: a FIFO, not a regular file"), std::string::npos) << run.err;
}

// ndtom-map --tiles writes the same map in tiles; ndtom-localize holds it by region and
// places every scan where the whole map does.
TEST(LocalizeEndToEnd, TiledMapFromNdtomMapGivesTheWholeMapsPoses) {
  Fixture f;
  const std::string tiled = (f.dir / "tiled").string();
  const ProgramRun mapped = runMapper(
      mapper_test::quoted(kLidar) + " --max-scans 5 --max-range 30 --no-pictures --tiles 2 -q -o " +
          mapper_test::quoted(tiled),
      f.dir);
  ASSERT_EQ(mapped.exit_code, 0) << mapped.err;
  const ndtom::TiledMapFile file(tiled + ".ndtomtiles");
  EXPECT_GT(file.tiles().size(), 10u);
  EXPECT_EQ(ndtom::encodeMap(file.loadAll()), ndtom::encodeMap(ndtom::loadMap(tiled + ".ndtom")));

  std::vector<std::vector<ndtom::io::StampedPose>> poses;
  for (const std::string& map : {f.map, tiled + ".ndtomtiles"}) {
    const std::string prefix = (f.dir / ("loc-" + std::to_string(poses.size()))).string();
    const ProgramRun run = runExecutable(
        kLocalize,
        mapper_test::quoted(map) + " " + mapper_test::quoted(f.scans.string()) + " -o " +
            mapper_test::quoted(prefix) + " --no-pictures --region-radius 20 --initial " +
            mapper_test::quoted(tumPose(f.offStart())),
        f.dir);
    ASSERT_EQ(run.exit_code, 0) << run.err;
    poses.push_back(ndtom::io::readPoseFile(prefix + ".tum", ndtom::io::PoseFormat::Tum));
  }
  ASSERT_EQ(poses[0].size(), 5u);
  ASSERT_EQ(poses[1].size(), 5u);
  for (size_t k = 0; k < 5; ++k)
    EXPECT_LT((poses[0][k].pose.translation() - poses[1][k].pose.translation()).norm(), 0.01) << k;
  const std::string json = readText((f.dir / "loc-1.summary.json").string());
  EXPECT_EQ(jsonNumber(json, "tiles_in_file"), double(file.tiles().size()));
  EXPECT_GT(jsonNumber(json, "loads"), 0);
}
