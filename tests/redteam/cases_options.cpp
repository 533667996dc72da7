// Issue #38, options in their documented ranges that cost or overflow downstream: ndtom-map's
// drawing options (--ellipsoid-detail, --min-eigen-abs, min_eigen_abs in a --config file), its
// memory and spill options, ndtom-worldgen's sizes, ndtom-rawlog-from-pcd on a full disk and
// ndtom-map-mpi's budget error.
#include <sys/stat.h>

#include <filesystem>
#include <fstream>

#include "cases.h"
#include "hostile_files.h"

namespace fs = std::filesystem;

namespace redteam {

std::vector<Case> optionCases(const Context& c) {
  if (c.worldgen.empty() || c.rawlog_from_pcd.empty()) return {};
  CaseSet set(c, "9 drawing, generator and spill options", "options");
  const std::string dir = set.dir;
  const auto lidar = [&c] { return sizeOf(c.lidar); };

  // ndtom-map on the ten shipped lidar scans with pictures (the drawing options act there).
  const auto map = [&](const std::string& name, std::vector<std::string> args, Expect expect,
                       double timeout, bool sampled = true) -> Case& {
    Case& k = set.add();
    k.name = name;
    k.expect = expect;
    k.sampled = sampled;
    k.limits.timeout_s = timeout;
    k.argv = c.mapper_args(c.lidar, set.path("/map"), args, /*pictures=*/true);
    k.setup = lidar;
    // A value that cannot be drawn is clamped or refused before the work, in our words.
    k.check = [](const Outcome& o) -> std::string {
      if (o.exit_code == 1 && o.err.find("Assertion failed") != std::string::npos)
        return "unclear: an OpenCV assertion after the work";
      return "";
    };
    return k;
  };
  // Class 1: --ellipsoid-detail D reserves 8*4^D triangles per Gaussian drawn.
  map("--ellipsoid-detail 4", {"--ellipsoid-detail", "4"}, Expect::Either, 120, false);
  map("--ellipsoid-detail 3", {"--ellipsoid-detail", "3"}, Expect::Either, 120, false);
  map("--ellipsoid-detail 4 --max-ellipsoids 10000000",
      {"--ellipsoid-detail", "4", "--max-ellipsoids", "10000000"}, Expect::Either, 120, false);
  map("--ellipsoid-detail 4 --resolution 0.1", {"--ellipsoid-detail", "4", "--resolution", "0.1"},
      Expect::Either, 120, false);
  // The widest picture allowed: supersampled, its 3D canvas alone took 1.25 GB.
  map("--image-width 8000", {"--image-width", "8000"}, Expect::Accept, 120, false);
  // Class 2: a large eigenvalue floor makes every ellipse huge: the pictures' work grows.
  map("--min-eigen-abs 1e3 (pictures)", {"--min-eigen-abs", "1e3"}, Expect::Either, 30, false);
  map("--min-eigen-abs 10 (pictures)", {"--min-eigen-abs", "10"}, Expect::Either, 30, false);
  // Class 3: a floor that cannot be drawn: clamped or refused before the work.
  for (const char* v : {"1e15", "1e300"})
    map(std::string("--min-eigen-abs ") + v + " (pictures)", {"--min-eigen-abs", v}, Expect::Either,
        60);
  map("--min-eigen-abs 1e300 --no-pictures (the scene only)",
      {"--min-eigen-abs", "1e300", "--no-pictures"}, Expect::Either, 60);
  for (const char* v : {"1e15", "1e300"}) {
    const std::string ini = dir + "/eigen-" + v + ".ini";
    Case& k = map(std::string("min_eigen_abs = ") + v + " in a --config file", {"--config", ini},
                  Expect::Either, 60);
    k.setup = [ini, v, lidar] {
      std::ofstream(ini) << "[MetricMap_ndtOccupancyMap_00_insertOpts]\nmin_eigen_abs = " << v
                         << "\n";
      return lidar();
    };
  }

  // Memory budget and spilling.
  map("--memory-budget 1 (MB)", {"--memory-budget", "1"}, Expect::Refuse, 60);
  map("--memory-budget 1e9 (MB, more than the machine)",
      {"--memory-budget", "1e9", "--no-pictures"}, Expect::Either, 60);
  map("--resident-budget 0.001 (1 kB of tiles resident)",
      {"--resident-budget", "0.001", "--max-scans", "3"}, Expect::Either, 60, false);
  // Class 6: a spill folder that cannot be made: the message names it (we may run as root, so
  // a path under a regular file, which no one can create).
  {
    const std::string file = dir + "/plain-file";
    const std::string spill = file + "/spill";
    Case& k = map("--spill-dir under a regular file",
                  {"--resident-budget", "1", "--spill-dir", spill, "--max-scans", "3"},
                  Expect::Refuse, 60);
    k.setup = [file, lidar] {
      std::ofstream(file) << "not a folder";
      return lidar();
    };
    k.check = [spill, file](const Outcome& o) -> std::string {
      if (o.exit_code == 1 && o.err.find(file) == std::string::npos)
        return "unclear: the message names no spill folder";
      return "";
    };
  }
  {
    const std::string ro = dir + "/read-only";
    Case& k =
        map("--spill-dir a read-only folder (mode 0555)",
            {"--resident-budget", "1", "--spill-dir", ro, "--max-scans", "3"}, Expect::Either, 60);
    k.setup = [ro, lidar] {
      fs::create_directories(ro);
      chmod(ro.c_str(), 0555);
      return lidar();
    };
    k.check = [ro](const Outcome& o) -> std::string {
      if (o.exit_code == 1 && o.err.find(ro) == std::string::npos)
        return "unclear: the message names no spill folder";
      return "";
    };
  }

  // ndtom-worldgen: sizes in range that allocate in proportion (class 1), and a drive too
  // long for the disk, refused up front (class 6) without scans left behind.
  const auto worldgen = [&](const std::string& name, std::vector<std::string> args, Expect expect,
                            double timeout, bool sampled = true) -> Case& {
    Case& k = set.add();
    k.name = "ndtom-worldgen " + name;
    k.expect = expect;
    k.sampled = sampled;
    k.limits.timeout_s = timeout;
    const std::string out = set.path("/city");
    k.argv = {c.worldgen, out, "-q", "--threads", "2"};
    k.argv.insert(k.argv.end(), args.begin(), args.end());
    k.check = [out](const Outcome& o) -> std::string {
      std::error_code ec;
      if (o.exit_code == 0 || !fs::is_directory(out, ec)) return "";
      int scans = 0;
      for (const auto& e : fs::directory_iterator(out, ec)) scans += e.path().extension() == ".pcd";
      if (scans > 0 && !fs::exists(out + "/poses.txt"))
        return "data loss: " + std::to_string(scans) + " scans of a failed run left in " + out;
      return "";
    };
    return k;
  };
  worldgen("--blocks 1000 --km 0.01", {"--blocks", "1000", "--km", "0.01"}, Expect::Either, 60,
           false);
  worldgen("--blocks 300 --km 0.01", {"--blocks", "300", "--km", "0.01"}, Expect::Either, 60,
           false);
  worldgen("--rings 512 --azimuth-steps 36000 --km 0.002",
           {"--rings", "512", "--azimuth-steps", "36000", "--km", "0.002"}, Expect::Either, 60,
           false);
  worldgen("--km 9000", {"--km", "9000"}, Expect::Either, 60, false);
  worldgen("--km 9000 --step 100", {"--km", "9000", "--step", "100"}, Expect::Either, 60, false);
  {
    Case& k = worldgen("--km 10000 --step 1 (refused up front)", {"--km", "10000", "--step", "1"},
                       Expect::Refuse, 60);
    const auto left = k.check;
    k.check = [left](const Outcome& o) -> std::string {
      if (o.exit_code != 0 && o.seconds > 2)
        return "unclear: refused after " + std::to_string(int(o.seconds)) + " s, not up front";
      return left(o);
    };
  }

  // ndtom-rawlog-from-pcd on a full disk: the message names the file.
  for (const uint64_t limit : {uint64_t(1), uint64_t(1000), uint64_t(100000)}) {
    Case& k = set.add();
    k.name = "ndtom-rawlog-from-pcd, files limited to " + std::to_string(limit) + " bytes";
    k.expect = Expect::Either;
    const std::string out = set.path("/rawlog");
    k.argv = {c.rawlog_from_pcd, c.lidar, "-o",          out + "/run", "-q",
              "--scans",         "0:2",   "--map-scans", "0:2"};
    k.limits.file_size = limit;
    k.limits.timeout_s = 60;
    k.setup = [out, lidar] {
      fs::create_directories(out);
      return lidar();
    };
    k.check = [out](const Outcome& o) -> std::string {
      if (o.exit_code == 1 && o.err.find(out) == std::string::npos)
        return "unclear: the message names no file";
      return "";
    };
  }
  {
    Case& k = set.add();
    k.name = "ndtom-rawlog-from-pcd, PREFIX.rawlog a link to /dev/full";
    k.expect = Expect::Either;
    const std::string out = set.path("/rawlog");
    k.argv = {c.rawlog_from_pcd, c.lidar, "-o", out + "/run", "-q", "--scans", "0:2"};
    k.limits.timeout_s = 60;
    k.setup = [out, lidar] {
      fs::create_directories(out);
      fs::create_symlink("/dev/full", out + "/run.rawlog");
      return lidar();
    };
    k.check = [out](const Outcome& o) -> std::string {
      if (o.exit_code == 1 && o.err.find(out) == std::string::npos)
        return "unclear: the message names no file";
      return "";
    };
  }

  // ndtom-map-mpi: a scan over the memory budget; the message names the scan.
  if (!c.mpi_mapper.empty() && fs::exists(c.mpi_mapper))
    for (const char* np : {"1", "2"}) {
      Case& k = set.add();
      k.name = std::string("ndtom-map-mpi -np ") + np + " --memory-budget 1";
      k.expect = Expect::Refuse;
      k.sampled = false;
      k.one_line = false;  // mpirun adds its own lines after an MPI_Abort
      k.limits.timeout_s = 60;
      k.argv = {"/usr/bin/env",
                "OMPI_ALLOW_RUN_AS_ROOT=1",
                "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1",
                "OMPI_MCA_rmaps_base_oversubscribe=1",
                "mpirun",
                "-np",
                np,
                c.mpi_mapper,
                c.lidar,
                "-o",
                set.path("/mpi"),
                "-q",
                "--no-pictures",
                "--memory-budget",
                "1"};
      k.setup = lidar;
      k.check = [](const Outcome& o) -> std::string {
        if (o.exit_code != 0 && o.err.find("full") == std::string::npos &&
            o.err.find("scan") == std::string::npos)
          return "unclear: the budget error names no scan";
        return "";
      };
    }
  return set.cases;
}

}  // namespace redteam
