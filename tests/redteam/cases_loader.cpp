// Classes 3, 4 and 5 of issue #17 at the loaders and the core API: counts that lie about
// the bytes, what insertion or setCell accept but loading refuses, and checksum-valid files
// whose values no map can hold.
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <sstream>

#include "cases.h"
#include "hostile_files.h"
#include "ndtom/files/map_io.h"
#include "ndtom_internal/crc32.h"
#include "support/ndtom_file_builder.h"

namespace redteam {
namespace {

using ndtom::testing::FileBuilder;

std::vector<uint8_t> withCrc(std::vector<uint8_t> b) {
  const uint32_t crc = ndtom::crc32(b.data(), b.size() - 4);
  for (int i = 0; i < 4; ++i) b[b.size() - 4 + size_t(i)] = uint8_t(crc >> (8 * i));
  return b;
}

ndtom::CellStats threePoints() {
  return ndtom::CellStats::fromPoints({{0.01, 0.02, -0.03}, {-0.05, 0.04, 0.01}, {0.02, 0, 0}});
}

// A small real map's file: header, options, cells. `count_at`: the u64 cell count, followed
// by the u64 block count and the u8 log-odds coding (the empty map's file ends there).
std::vector<uint8_t> smallFile(size_t* count_at) {
  ndtom::NdtMap map;
  map.insertScan(pointsAround({0, 0, 0}, 2, 300, 3), {0.05, 0.05, 0.05});
  const auto bytes = ndtom::encodeMap(map);
  *count_at = ndtom::encodeMap(ndtom::NdtMap()).size() - 4 - 17;
  return bytes;
}

// The .ndtommap archive of ndtomMapBytes() with its map data replaced by `file`.
std::vector<uint8_t> inArchive(const std::vector<uint8_t>& file) {
  size_t size_at = 0;
  std::vector<uint8_t> archive = ndtommapBytes(&size_at);
  uint64_t old_size;
  std::memcpy(&old_size, &archive[size_at], 8);
  std::vector<uint8_t> out(archive.begin(), archive.begin() + std::ptrdiff_t(size_at));
  const uint64_t size = file.size();
  out.insert(out.end(), reinterpret_cast<const uint8_t*>(&size),
             reinterpret_cast<const uint8_t*>(&size) + 8);
  out.insert(out.end(), file.begin(), file.end());
  out.insert(out.end(), archive.begin() + std::ptrdiff_t(size_at + 8 + old_size), archive.end());
  return out;
}

// The probe's `command` on `bytes` written to a fresh file ending in `suffix`.
void addProbeCase(CaseSet& set, const std::string& name, const std::string& command,
                  const std::string& suffix, const std::vector<uint8_t>& bytes,
                  Expect expect = Expect::Refuse) {
  const std::string path = set.path(suffix);
  Case& k = set.add();
  k.name = name;
  k.expect = expect;
  k.argv = {set.c.probe, command, path};
  k.limits.timeout_s = 60;
  k.setup = [path, bytes] {
    writeFile(path, bytes);
    if (!std::filesystem::is_regular_file(path))  // a harness mistake, not a finding
      throw std::logic_error("ndtom-redteam: cannot write " + path);
    return sizeOf(path);
  };
}

}  // namespace

std::vector<Case> loaderCountCases(const Context& c) {
  CaseSet set(c, "3 loader allocations", "loader");
  size_t count_at = 0;
  const std::vector<uint8_t> small = smallFile(&count_at);
  // The red team's file: a count overlaps the checksum (remaining() - 4 underflowed); in
  // format 2, the block count after the cell count.
  const std::vector<uint8_t> head(small.begin(), small.begin() + std::ptrdiff_t(count_at + 8));
  for (const uint32_t low : {0u, 1u, 2u, 100u, 5000u, 1000000u, 0x7FFFFFFFu, 0xFFFFFFFFu}) {
    std::vector<uint8_t> f = head;
    for (int i = 0; i < 4; ++i) f.push_back(uint8_t(low >> (8 * i)));
    const uint32_t crc = ndtom::crc32(f.data(), f.size());
    for (int i = 0; i < 4; ++i) f.push_back(uint8_t(crc >> (8 * i)));
    for (const char* command : {"load-ndtom", "load-ndtommap"})
      addProbeCase(set,
                   std::string(command) + ", count overlaps the CRC, low " + std::to_string(low),
                   command, ".x", std::string(command) == "load-ndtom" ? f : inArchive(f));
  }
  for (const auto& [field, at] : {std::pair{"cell", count_at}, std::pair{"block", count_at + 8}}) {
    uint64_t real_count;
    std::memcpy(&real_count, &small[at], 8);
    for (const uint64_t count : {real_count + 1, real_count - 1, real_count + 1000,
                                 uint64_t(1) << 31, uint64_t(1700000000), uint64_t(1) << 32,
                                 uint64_t(1) << 40, uint64_t(1) << 62, ~uint64_t(0)}) {
      std::vector<uint8_t> f = small;
      std::memcpy(&f[at], &count, 8);
      f = withCrc(f);
      for (const char* command : {"load-ndtom", "load-ndtommap"})
        addProbeCase(set, std::string(command) + ", " + field + " count " + std::to_string(count),
                     command, ".x", std::string(command) == "load-ndtom" ? f : inArchive(f));
    }
  }
  // The dictionary size, a varint after the coding byte: 2^63 and 2^31 values.
  for (const uint64_t size : {uint64_t(1) << 63, uint64_t(1) << 31}) {
    std::vector<uint8_t> f(small.begin(), small.begin() + std::ptrdiff_t(count_at + 17));
    uint64_t v = size;
    for (; v >= 0x80; v >>= 7) f.push_back(uint8_t(v | 0x80));
    f.push_back(uint8_t(v));
    f.insert(f.end(), small.begin() + std::ptrdiff_t(count_at + 18), small.end());
    addProbeCase(set, "dictionary size " + std::to_string(size), "load-ndtom", ".ndtom",
                 withCrc(f));
  }
  for (const uint32_t options : {12u, 256u, 257u, 0xFFFFFFFFu}) {
    std::vector<uint8_t> f = small;
    std::memcpy(&f[12], &options, 4);
    addProbeCase(set, "option count " + std::to_string(options), "load-ndtom", ".ndtom",
                 withCrc(f));
  }
  for (size_t len = 0; len < small.size(); len += std::max<size_t>(1, small.size() / 40))
    addProbeCase(set, "truncated at " + std::to_string(len), "load-ndtom", ".ndtom",
                 std::vector<uint8_t>(small.begin(), small.begin() + std::ptrdiff_t(len)));
  // The archive's size field, and the archive cut short.
  size_t size_at = 0;
  const std::vector<uint8_t> archive = ndtommapBytes(&size_at);
  uint64_t data_size;
  std::memcpy(&data_size, &archive[size_at], 8);
  for (const uint64_t size : {~uint64_t(0), uint64_t(1) << 62, uint64_t(1) << 40,
                              uint64_t(10000000000), data_size + 1, data_size - 1, uint64_t(0)}) {
    std::vector<uint8_t> f = archive;
    std::memcpy(&f[size_at], &size, 8);
    addProbeCase(set, "archive map size " + std::to_string(size), "load-ndtommap", ".ndtommap", f);
  }
  for (size_t len = 1; len < archive.size(); len += archive.size() / 12)
    addProbeCase(set, "archive truncated at " + std::to_string(len), "load-ndtommap", ".ndtommap",
                 std::vector<uint8_t>(archive.begin(), archive.begin() + std::ptrdiff_t(len)));
  // A gzip archive announcing 2 GB of map data, 2 MB compressed.
  {
    addProbeCase(set, "gzip archive announcing 2 GB of map data", "load-ndtommap", ".ndtommap.gz",
                 {});
    Case& k = set.cases.back();
    const std::string gz = k.argv.back();
    std::vector<uint8_t> prefix(archive.begin(), archive.begin() + std::ptrdiff_t(size_at));
    k.setup = [gz, prefix] {
      gzFile f = gzopen(gz.c_str(), "wb9");
      gzwrite(f, prefix.data(), unsigned(prefix.size()));
      const uint64_t size = uint64_t(2) << 30;
      gzwrite(f, &size, 8);
      const std::vector<uint8_t> zeros(1 << 20, 0);
      for (int i = 0; i < 2048; ++i) gzwrite(f, zeros.data(), unsigned(zeros.size()));
      gzclose(f);
      return sizeOf(gz);
    };
  }
  // Cells scattered one to a block: 20 bytes of file each, a 2 kB block each in memory.
  for (const int cells : {50000, 250000, 500000}) {
    FileBuilder f;
    f.cells(uint64_t(cells));
    for (int i = 0; i < cells; ++i) f.cell({16 * (i % 1000), 16 * (i / 1000), 0}, -0.5f);
    addProbeCase(set, std::to_string(cells) + " cells, one per block", "load-ndtom", ".ndtom",
                 f.finish(), Expect::Either);
  }
  return set.cases;
}

std::vector<Case> writableCases(const Context& c) {
  CaseSet set(c, "4 writable means loadable", "writable");
  const std::string& dir = set.dir;
  int& id = set.id;
  auto add = [&](const std::string& name, std::vector<std::string> args, Expect expect) {
    const std::string out = set.path(".ndtom");
    Case& k = set.add();
    k.name = name;
    k.expect = expect;
    k.argv = {c.probe};
    k.argv.insert(k.argv.end(), args.begin(), args.end());
    k.argv.push_back(out);
    k.limits.timeout_s = 30;
    k.setup = [] { return uint64_t(100); };
  };
  auto num = [](double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
  };
  const double top = double((1 << 30) - 1);
  // The outermost cells on each axis, from inside, at several resolutions.
  for (const double r : {0.05, 0.1, 0.3, 1.0})
    for (int axis = 0; axis < 3; ++axis)
      for (const double side : {-1.0, 1.0}) {
        double p[3] = {0.01, 0.01, 0.01};
        p[axis] = (side > 0 ? top + 0.5 : -top + 0.5) * r;  // in cell +-(2^30 - 1)
        if (axis != 0) p[0] = 0.5 * r;                      // the probe steps its origin along x
        add("insert in cell " + std::string(side < 0 ? "-" : "+") + "(2^30-1) on axis " +
                std::to_string(axis) + " at " + num(r) + " m",
            {"writable-insert", num(r), num(p[0]), num(p[1]), num(p[2])}, Expect::Accept);
      }
  // Points a few ulps below a cell's upper face, far from the origin.
  std::mt19937 rng(5);
  for (int k = 0; k < 40; ++k) {
    const double r = k % 2 ? 0.1 : 0.05;
    double x = std::nextafter((double((1 << 30) - 2 - int(rng() % 1000000)) + 1) * r, 0.0);
    if (k % 4 >= 2)
      x = -std::nextafter((double((1 << 30) - 3 - int(rng() % 1000000)) + 1) * r, 0.0);
    add("insert just below a cell face at " + num(x) + " m",
        {"writable-insert", num(r), num(x), "0.05", "0.05"}, Expect::Accept);
  }
  // setCell: what it takes must save and load.
  const std::vector<std::pair<std::string, std::vector<std::string>>> set_cells = {
      {"NaN log-odds", {"0", "0", "0", "nan", "0", "0"}},
      {"inf log-odds", {"0", "0", "0", "inf", "0", "0"}},
      {"index -(2^30-1)", {"-1073741823", "0", "0", "1", "0", "0"}},
      {"index 2^30-1", {"1073741823", "0", "0", "1", "0", "0"}},
      {"index 2^30", {"1073741824", "0", "0", "1", "0", "0"}},
      {"index -2^31", {"-2147483648", "0", "0", "1", "0", "0"}},
      {"statistics in an empty cell", {"0", "0", "0", "-1", "3", "0"}},
      {"mean outside the cell", {"0", "0", "0", "1", "3", "0.3"}},
      {"one point with a spread", {"0", "0", "0", "1", "1", "0"}},
  };
  for (const auto& [name, args] : set_cells) {
    std::vector<std::string> a = {"writable-setcell"};
    a.insert(a.end(), args.begin(), args.end());
    add("setCell " + name, a, Expect::Either);
  }
  // ndtom-map on a scan in the outermost cells: its outputs must load.
  for (const double r : {0.1, 0.2, 1.0})
    for (const double side : {-1.0, 1.0}) {
      Case& k = set.add();
      k.name = "ndtom-map, a scan in the outermost cells at " + num(r) + " m, side " + num(side);
      k.expect = Expect::Accept;
      const std::string folder = dir + "/edge" + std::to_string(id++);
      // Some points in the outermost cell, some beyond (rejected and counted).
      const Eigen::Vector3d centre((side > 0 ? top - 5 : -top + 5) * r, 0.1, 0.1);
      k.argv = c.mapper_args(folder, folder + "-out/out",
                             {"--resolution", num(r), "--max-range", num(30 * r)});
      k.setup = [folder, centre, r, side] {
        std::filesystem::create_directories(folder);
        // In the sensor's frame, outwards from it; the pose puts the sensor at `centre`.
        auto pts = pointsAround({0, 0, 0}, 10 * r, 500, 2);
        for (auto& p : pts) p.x() = side * std::abs(p.x());
        writeFile(folder + "/scan.pcd", pcdHeader(pts.size(), "binary") + pcdBinaryPoints(pts));
        writeFile(folder + "/poses.txt", kittiPoses({centre}));
        return sizeOf(folder);
      };
      const std::string out = folder + "-out/out";
      const std::string probe = c.probe;
      k.check = [out, probe](const Outcome& o) -> std::string {
        if (o.exit_code != 0) return "";
        for (const auto& [command, ext] :
             {std::pair{"load-ndtom", ".ndtom"}, std::pair{"load-ndtommap", ".ndtommap"}}) {
          const Outcome load = runCommand({probe, command, out + ext});
          if (load.exit_code != 0)
            return std::string("data loss: ") + ext + " written but not loadable";
        }
        return "";
      };
    }
  return set.cases;
}

std::vector<Case> silentValueCases(const Context& c) {
  CaseSet set(c, "5 silent wrong values", "silent");
  const std::string& dir = set.dir;
  int& id = set.id;
  const ndtom::MapOptions o;
  const double half = 0.5 * o.resolution;
  auto oneCell = [](ndtom::CellStats s, float logodds = 1.f, const std::string& option = "",
                    double value = 0) {
    FileBuilder f({}, option, value);
    f.cells(1);
    f.cell({1, 2, 3}, logodds, s);
    return f.finish();
  };
  auto text = [](double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  };
  std::vector<std::pair<std::string, std::vector<uint8_t>>> files;
  for (const double b : {0.5, 2.0, std::nan(""), -1.0, double(INFINITY), 1e-300})
    files.push_back({"occupancy_enabled stored as " + text(b),
                     oneCell(threePoints(), 1.f, "occupancy_enabled", b)});
  for (const double m : {0.5, 2.0})
    files.push_back({"ray_mode " + text(m), oneCell({}, 1.f, "ray_mode", m)});
  ndtom::CellStats s = threePoints();
  s.scatter(0, 1) = s.scatter(1, 0) = 2 * std::sqrt(s.scatter(0, 0) * s.scatter(1, 1));
  files.push_back({"scatter with |s01| > sqrt(s00 s11)", oneCell(s)});
  s = threePoints();
  s.scatter(2, 2) = -1e-4;
  files.push_back({"negative variance", oneCell(s)});
  s = threePoints();
  s.scatter << 1, 0.9, 0.9, 0.9, 1, -0.9, 0.9, -0.9, 1;  // minors > 0, determinant < 0
  s.scatter *= 1e-3;
  files.push_back({"scatter with a negative determinant", oneCell(s)});
  for (const double m :
       {half * (1 + 5e-10), std::nextafter(half, 1.0), 0.6 * o.resolution, 10 * o.resolution}) {
    s = threePoints();
    s.relative_mean.x() = m;
    std::ostringstream name;
    name.precision(17);
    name << "mean " << m << " from the centre of a " << o.resolution << " m cell";
    files.push_back({name.str(), oneCell(s)});
  }
  s = threePoints();
  s.n = 1;
  files.push_back({"one point with a spread", oneCell(s)});
  s.scatter.setZero();
  s.scatter(1, 1) = 1e-20;
  files.push_back({"one point with a tiny spread", oneCell(s)});
  files.push_back({"statistics in an empty cell", oneCell(threePoints(), -0.5f)});
  files.push_back({"log-odds above the clamp", oneCell({}, 9.f)});
  files.push_back({"NaN log-odds", oneCell({}, std::nanf(""))});
  s = threePoints();
  s.scatter(0, 0) = std::nan("");
  files.push_back({"NaN scatter", oneCell(s)});
  {
    FileBuilder f;
    f.cells(2);
    f.cell({4, 5, 6}, 1.f, threePoints());
    f.cell({4, 5, 6}, 2.f, threePoints());
    files.push_back({"duplicate cell", f.finish()});
  }
  for (const auto& [name, file] : files) {
    addProbeCase(set, ".ndtom: " + name, "load-ndtom", ".ndtom", file);
    addProbeCase(set, ".ndtommap: " + name, "load-ndtommap", ".ndtommap", inArchive(file));
  }
  // Poses that are not poses: mirrors, and files mixing KITTI and TUM lines.
  const std::vector<std::pair<std::string, std::string>> poses = {
      {"KITTI mirror in x", "-1 0 0 0 0 1 0 0 0 0 1 0\n"},
      {"KITTI mirror in y", "1 0 0 0 0 -1 0 0 0 0 1 0\n"},
      {"KITTI mirror in z", "1 0 0 0 0 1 0 0 0 0 -1 0\n"},
      {"KITTI point reflection", "-1 0 0 0 0 -1 0 0 0 0 -1 0\n"},
      {"KITTI mirror after a good line", "1 0 0 0 0 1 0 0 0 0 1 0\n0 1 0 0 1 0 0 0 0 0 1 0\n"},
      {"KITTI then TUM", "1 0 0 0 0 1 0 0 0 0 1 0\n5.0 1 2 3 0 0 0 1\n"},
      {"TUM then KITTI", "5.0 1 2 3 0 0 0 1\n1 0 0 0 0 1 0 0 0 0 1 0\n"},
      {"KITTI scaled by 2", "2 0 0 0 0 2 0 0 0 0 2 0\n"},
  };
  for (const auto& [name, text] : poses) {
    addProbeCase(set, "poses: " + name, "poses", ".txt",
                 std::vector<uint8_t>(text.begin(), text.end()));
    // And as the poses of a PCD folder of as many scans.
    Case& k = set.add();
    k.name = "ndtom-map, poses: " + name;
    const std::string folder = dir + "/pf" + std::to_string(id++);
    k.argv = c.mapper_args(folder, folder + "-out/out", {});
    const int lines = int(std::count(text.begin(), text.end(), '\n'));
    k.setup = [&c, folder, text, lines] {
      c.lidarFolder(std::filesystem::path(folder).lexically_relative(c.work).string(), lines);
      writeFile(folder + "/poses.txt", text);
      return sizeOf(folder);
    };
  }
  // Point counts that wrap in merge and coarsening.
  for (const char* n : {"2147483648", "3000000000", "4294967295"}) {
    Case& k = set.add();
    k.name = "merge and coarsen cells of " + std::string(n) + " points";
    k.expect = Expect::Accept;
    k.argv = {c.probe, "saturate", n};
    k.setup = [] { return uint64_t(0); };
  }
  return set.cases;
}

}  // namespace redteam
