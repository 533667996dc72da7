// Class 2 of issue #17: small inputs whose geometry (far points, a fine resolution, large
// images, scattered scans) would take gigabytes. A correct run maps them or refuses them
// with a clear message, within the memory budget.
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <sstream>

#include "cases.h"
#include "hostile_files.h"

namespace redteam {
namespace {

// The summary accounts for every point given: "in" equals the points written.
std::function<std::string(const Outcome&)> accountsFor(const std::string& summary, size_t points) {
  return [summary, points](const Outcome& o) -> std::string {
    if (o.exit_code != 0) return "";
    const std::string json = readFile(summary);
    const size_t at = json.find("\"in\": ");
    if (at == std::string::npos) return "silent wrong: no summary";
    const size_t in = std::stoul(json.substr(at + 6));
    return in == points ? "" : "silent wrong: " + std::to_string(in) + " points reported";
  };
}

// ndtom-map on a fresh input folder that `fill` writes, its outputs beside it.
Case& folderCase(CaseSet& set, const std::string& name, double timeout,
                 std::function<void(const std::string& folder)> fill,
                 const std::vector<std::string>& args = {}, bool pictures = false) {
  const std::string folder = set.path("");
  Case& k = set.add();
  k.name = name;
  k.expect = Expect::Either;
  k.limits.timeout_s = timeout;
  k.argv = set.c.mapper_args(folder, folder + "-out/out", args, pictures);
  k.setup = [folder, fill] {
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    fill(folder);
    return sizeOf(folder);
  };
  return k;
}

// One scan at the origin, as a PCD folder.
void writeOneScan(const std::string& folder, const std::string& pcd) {
  writeFile(folder + "/scan.pcd", pcd);
  writeFile(folder + "/poses.txt", kittiPoses({{0, 0, 0}}));
}

// A binary_compressed PCD of `points` identical points: per column a literal float, then
// back-references of 264 bytes to it (LZF's longest, 88 times their 3 bytes).
std::string repeatedPointPcd(uint64_t points) {
  std::string packed;
  for (int a = 0; a < 3; ++a) {
    const float v = float(a + 1);
    packed.push_back(3);
    packed.append(reinterpret_cast<const char*>(&v), 4);
    for (uint64_t done = 4; done < points * 4;) {
      // Lengths are multiples of 4 (264 is), so the last one is 4 or more.
      const uint64_t len = std::min<uint64_t>(264, points * 4 - done);
      if (len >= 9) {
        packed.push_back(char(7 << 5));
        packed.push_back(char(len - 2 - 7));
      } else {
        packed.push_back(char((len - 2) << 5));
      }
      packed.push_back(3);  // 4 bytes back: the same float again
      done += len;
    }
  }
  std::string file = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " +
                     std::to_string(points) + "\nHEIGHT 1\nPOINTS " + std::to_string(points) +
                     "\nDATA binary_compressed\n";
  const uint32_t sizes[2] = {uint32_t(packed.size()), uint32_t(points * 12)};
  file.append(reinterpret_cast<const char*>(sizes), 8);
  return file + packed;
}

}  // namespace

std::vector<Case> geometryMemoryCases(const Context& c) {
  CaseSet set(c, "2 work and memory vs geometry", "memory");
  // One scan of n points `range` metres from the sensor.
  for (const int n : {1, 10, 100, 1000, 10000})
    for (const double range : {150.0, 1000.0, 6000.0, 60000.0, 1e6})
      for (const bool unlimited : {false, true}) {
        std::ostringstream name;
        name << n << " points at " << range << " m" << (unlimited ? ", --max-range inf" : "");
        const std::vector<std::string> args = {"--max-range", "inf"};
        Case& k = folderCase(
            set, name.str(), 120,
            [n, range](const std::string& folder) {
              writeOneScan(folder, pcdHeader(uint64_t(n), "binary") +
                                       pcdBinaryPoints(pointsAround({0, 0, 0}, range, n, 7)));
            },
            unlimited ? args : std::vector<std::string>{},
            n == 100);  // the red team's case, with the pictures as well
        k.check = accountsFor(k.argv[3] + ".summary.json", size_t(n));
      }
  // A fine resolution on one real frame: the TUM depth image and a lidar scan.
  for (const double r : {0.001, 0.002, 0.005, 0.01, 0.02})
    for (const bool lidar : {false, true}) {
      Case& k = set.add();
      std::ostringstream name, res;
      name << "--resolution " << r << (lidar ? ", one lidar scan" : ", one TUM frame");
      res << r;
      k.name = name.str();
      k.expect = Expect::Either;
      const std::string input = lidar ? c.work + "/fine-lidar" : c.tum;
      k.argv = c.mapper_args(input, set.path("/out"),
                             {"--resolution", res.str(), "--max-scans", "1"}, true);
      k.limits.timeout_s = 180;
      k.setup = [&c, lidar, input] {
        if (lidar && !std::filesystem::exists(input)) c.lidarFolder("fine-lidar", 1);
        return lidar ? sizeOf(input + "/full0.pcd") : uint64_t(140000);  // one depth PNG
      };
    }
  // The red team's 153-byte rawlog: one 2D scan of 361 rays, at 6 km and farther.
  for (const float range : {6000.f, 60000.f, 1e6f})
    for (const bool unlimited : {false, true}) {
      Case& k = set.add();
      k.name = "rawlog, one 2D scan at " + std::to_string(int(range)) + " m" +
               (unlimited ? ", --max-range inf" : "");
      k.expect = Expect::Either;
      const std::string log = set.path(".rawlog");
      k.argv = c.mapper_args(
          log, log + "-out/out",
          unlimited ? std::vector<std::string>{"--max-range", "inf"} : std::vector<std::string>{});
      k.limits.timeout_s = 120;
      k.setup = [log, range] {
        writeLaserRawlog(log, 1, range);
        return sizeOf(log);
      };
    }
  // Depth images that are small files but large images.
  for (const auto& [w, h, value] : std::vector<std::array<uint32_t, 3>>{{4000, 4000, 5000},
                                                                        {4000, 4000, 0},
                                                                        {5000, 5000, 10000},
                                                                        {8192, 8192, 2000},
                                                                        {32768, 32767, 0},
                                                                        {20000, 20000, 1}}) {
    folderCase(set,
               "TUM depth PNG " + std::to_string(w) + " x " + std::to_string(h) + " of " +
                   std::to_string(value),
               180, [w = w, h = h, value = value](const std::string& folder) {
                 std::filesystem::create_directories(folder + "/depth");
                 writeFlatPng(folder + "/depth/1.0.png", w, h, uint16_t(value));
                 writeFile(folder + "/associations.txt",
                           "rgb/1.0.png depth/1.0.png 0 0 0 0 0 0 1\n");
               });
  }
  // binary_compressed PCDs: LZF expands a run 88 times at most.
  for (const uint64_t points : {uint64_t(1) << 20, uint64_t(1) << 23, uint64_t(1) << 25})
    folderCase(
        set, "compressed PCD of " + std::to_string(points) + " identical points", 180,
        [points](const std::string& folder) { writeOneScan(folder, repeatedPointPcd(points)); });
  // Many small scans far apart: each fits, together they grow the map without end.
  for (const int scans : {100, 400})
    folderCase(set, std::to_string(scans) + " scans of 2000 points at 60 m, 1 km apart", 300,
               [scans](const std::string& folder) {
                 std::vector<Eigen::Vector3d> origins;
                 for (int s = 0; s < scans; ++s) {
                   origins.push_back({1000.0 * (s % 20), 1000.0 * (s / 20), 0});
                   writeFile(folder + "/s" + std::to_string(s) + ".pcd",
                             pcdHeader(2000, "binary") +
                                 pcdBinaryPoints(pointsAround({0, 0, 0}, 60, 2000, unsigned(s))));
                 }
                 writeFile(folder + "/poses.txt", kittiPoses(origins));
               });
  return set.cases;
}

}  // namespace redteam
