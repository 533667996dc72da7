// Class 7 of issue #17: damaged MRPT rawlogs. MRPT 2.5.8's own reader crashes on some (its
// allocator returns NULL for a huge size and the vector is then written): such a crash is
// MRPT's when MRPT's reader alone (the probe's mrpt-read) crashes on the same file too.
#include <cstring>
#include <filesystem>
#include <random>

#include "cases.h"
#include "hostile_files.h"

namespace redteam {

std::vector<Case> rawlogCases(const Context& c) {
  CaseSet set(c, "7 corrupt MRPT rawlogs", "rawlog");
  const std::string& dir = set.dir;
  const std::string good = dir + "/good.rawlog";
  writeLaserRawlog(good, 6, 8.0f);
  const std::string bytes = readFile(good);
  // Where the scans' ray counts (361, u32) are: the sizes MRPT's reader allocates from.
  std::vector<size_t> counts;
  for (size_t at = bytes.find(std::string("\x69\x01\0\0", 4)); at != std::string::npos;
       at = bytes.find(std::string("\x69\x01\0\0", 4), at + 1))
    counts.push_back(at);
  std::mt19937 rng(11);
  for (int k = 0; k < 72; ++k) {
    std::string damaged = bytes;
    std::string name;
    if (k >= 60) {  // a ray count set to a huge size
      const uint32_t sizes[3] = {0xFFFFFFFFu, 0x80000000u, 1000000000u};
      const size_t at = counts[size_t(k - 60) / 3 % counts.size()];
      std::memcpy(&damaged[at], &sizes[(k - 60) % 3], 4);
      name = "a ray count at byte " + std::to_string(at) + " set to " +
             std::to_string(sizes[(k - 60) % 3]);
    } else if (k < 10) {  // cut short
      const size_t len = bytes.size() * size_t(k + 1) / 11;
      damaged.resize(len);
      name = "truncated at " + std::to_string(len);
    } else if (k < 35) {  // random bytes set to 0xFF (counts, sizes)
      for (int i = 0; i < 1 + k % 3; ++i) damaged[rng() % damaged.size()] = char(0xFF);
      name = "bytes set to 0xFF, seed step " + std::to_string(k);
    } else {  // random bit flips
      for (int i = 0; i < 1 + k % 4; ++i) damaged[rng() % damaged.size()] ^= char(1 << (rng() % 8));
      name = "bits flipped, seed step " + std::to_string(k);
    }
    const std::string path = dir + "/d" + std::to_string(k) + ".rawlog";
    Case& kase = set.add();
    kase.name = name;
    kase.expect = Expect::Either;  // a flip may leave a valid log
    kase.argv = c.mapper_args(path, dir + "/out" + std::to_string(k) + "/out", {});
    kase.limits.timeout_s = 60;
    kase.setup = [path, damaged] {
      writeFile(path, damaged);
      return uint64_t(damaged.size());
    };
    const std::string probe = c.probe;
    kase.check = [probe, path](const Outcome& o) -> std::string {
      if (o.signal == 0) return "";
      const Outcome mrpt = runCommand({probe, "mrpt-read", path});
      return mrpt.signal != 0 ? "mrpt: MRPT's reader alone crashes on it too" : "";
    };
  }
  return set.cases;
}

}  // namespace redteam
