// Class 7 of issue #17: option mistakes, special files where files are expected.
#include <sys/stat.h>

#include <filesystem>

#include "cases.h"
#include "hostile_files.h"

namespace fs = std::filesystem;

namespace redteam {

std::vector<Case> smallCases(const Context& c) {
  CaseSet set(c, "7 small ones", "small");
  const std::string& dir = set.dir;
  // The expected exit status, checked: 2 for a bad command line, 1 for bad data.
  auto add = [&](const std::string& name, const std::string& input, std::vector<std::string> args,
                 int status, std::function<uint64_t()> setup) {
    Case& k = set.add();
    k.name = name;
    k.argv = c.mapper_args(input, set.path("/out"), args);
    k.limits.timeout_s = 30;
    k.setup = setup;
    k.check = [status](const Outcome& o) -> std::string {
      if (o.exit_code == 1 || o.exit_code == 2)
        return o.exit_code == status ? "" : "unclear: exit status " + std::to_string(o.exit_code);
      return "";
    };
  };
  const auto none = [] { return uint64_t(0); };
  const std::string scans = dir + "/scans";
  const auto lidar3 = [&c] { return sizeOf(c.lidarFolder("small/scans", 3)); };
  add("--poses /nonexistent (rawlog)",
      "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom "
      "Faculty_one_loop_only.rawlog",
      {"--poses", "/nonexistent"}, 2, none);
  add("--poses /nonexistent (PCD folder)", scans, {"--poses", "/nonexistent"}, 2, lidar3);
  add("--poses a folder", scans, {"--poses", dir}, 2, lidar3);
  add("--resolution 600 --coarse 2", c.tum, {"--resolution", "600", "--coarse", "2"}, 2, none);
  add("--resolution 999 --coarse 64", c.tum, {"--resolution", "999", "--coarse", "64"}, 2, none);
  add("--config a folder", c.tum, {"--config", dir}, 2, none);
  // Special files where files are expected (a FIFO hangs a reader; /dev/zero never ends).
  const std::string fifo = dir + "/fifo";
  const auto makeFifo = [fifo] {
    fs::remove(fifo);
    mkfifo(fifo.c_str(), 0600);
    return uint64_t(0);
  };
  add("FIFO as --poses", scans, {"--poses", fifo}, 2, [=] { return lidar3() + makeFifo(); });
  add("FIFO as --config", c.tum, {"--config", fifo}, 2, makeFifo);
  add("/dev/zero as --poses", scans, {"--poses", "/dev/zero"}, 2, lidar3);
  add("/dev/zero as --config", c.tum, {"--config", "/dev/zero"}, 2, none);
  add("/dev/zero as the rawlog", "/dev/zero", {"--format", "rawlog"}, 2, none);
  add("/dev/zero as the simplemap", "/dev/zero", {"--format", "simplemap"}, 2, none);
  add("/dev/urandom as the rawlog", "/dev/urandom", {"--format", "rawlog"}, 2, none);
  const std::string named = dir + "/named.rawlog";
  add("FIFO named run.rawlog", named, {}, 2, [named] {
    fs::remove(named);
    mkfifo(named.c_str(), 0600);
    return uint64_t(0);
  });
  add("FIFO named scan.pcd in a PCD folder", scans, {}, 1, [&c, scans] {
    const uint64_t bytes = sizeOf(c.lidarFolder("small/scans", 3));
    fs::remove(scans + "/full1.pcd");
    mkfifo((scans + "/full1.pcd").c_str(), 0600);
    return bytes;
  });
  add("/dev/zero as scan.pcd (a symlink)", scans, {}, 1, [&c, scans] {
    const uint64_t bytes = sizeOf(c.lidarFolder("small/scans", 3));
    fs::remove(scans + "/full1.pcd");
    fs::create_symlink("/dev/zero", scans + "/full1.pcd");
    return bytes;
  });
  add("/dev/zero as poses.txt (a symlink)", scans, {}, 1, [&c, scans] {
    const uint64_t bytes = sizeOf(c.lidarFolder("small/scans", 3));
    fs::remove(scans + "/poses.txt");
    fs::create_symlink("/dev/zero", scans + "/poses.txt");
    return bytes;
  });
  const std::string tum = dir + "/tum";
  const auto tumCopy = [&c, tum] {
    fs::remove_all(tum);
    fs::copy(c.tum, tum, fs::copy_options::recursive);
    return sizeOf(tum);
  };
  add("FIFO as a TUM depth image", tum, {}, 1, [=] {
    const uint64_t bytes = tumCopy();
    for (const auto& e : fs::directory_iterator(tum + "/depth")) {
      fs::remove(e.path());
      mkfifo(e.path().c_str(), 0600);
      break;
    }
    return bytes;
  });
  add("FIFO as associations.txt", tum, {}, 1, [=] {
    const uint64_t bytes = tumCopy();
    fs::remove(tum + "/associations.txt");
    mkfifo((tum + "/associations.txt").c_str(), 0600);
    return bytes;
  });
  add("/dev/zero as associations.txt", tum, {}, 1, [=] {
    const uint64_t bytes = tumCopy();
    fs::remove(tum + "/associations.txt");
    fs::create_symlink("/dev/zero", tum + "/associations.txt");
    return bytes;
  });
  return set.cases;
}

}  // namespace redteam
