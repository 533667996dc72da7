// A save that fails at any byte (the file-size limit makes write() fail, as a full disk
// would) leaves the previous map file intact and loadable, and no temporary behind.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <random>

#include "ndtom/files/map_io.h"

using Eigen::Vector3d;

namespace {

ndtom::NdtMap mapOf(int points, unsigned seed) {
  ndtom::NdtMap map;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-5, 5);
  std::vector<Vector3d> pts;
  for (int i = 0; i < points; ++i) pts.emplace_back(u(rng), u(rng), -1.0);
  map.insertScan(pts, Vector3d(0, 0, 0.5));
  return map;
}

// Runs saveMap(map, path) in a child process whose files may not exceed `limit` bytes.
// Returns true if the save reported failure (threw).
bool saveFailsWithFileSizeLimit(const ndtom::NdtMap& map, const std::string& path, rlim_t limit) {
  const pid_t pid = fork();
  if (pid == 0) {
    signal(SIGXFSZ, SIG_IGN);  // write() then fails with EFBIG instead of killing us
    const rlimit rl{limit, limit};
    setrlimit(RLIMIT_FSIZE, &rl);
    try {
      ndtom::saveMap(map, path);
    } catch (const std::runtime_error&) {
      _exit(0);
    }
    _exit(1);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

// Temporaries of `path` left by any process (the child has its own pid).
int leftoverTemporaries(const std::string& path) {
  const std::filesystem::path p(path);
  const std::string prefix = p.filename().string() + ".ndtom-tmp-";
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(p.parent_path()))
    n += entry.path().filename().string().rfind(prefix, 0) == 0;
  return n;
}

}  // namespace

TEST(AtomicSave, FailedWritesAtAnyByteKeepThePreviousFile) {
  const std::string path = ::testing::TempDir() + "/atomic-" + std::to_string(getpid()) + ".ndtom";
  const ndtom::NdtMap old_map = mapOf(500, 1);
  const ndtom::NdtMap new_map = mapOf(3000, 2);
  ndtom::saveMap(old_map, path);
  const auto old_bytes = ndtom::encodeMap(old_map);
  const size_t new_size = ndtom::encodeMap(new_map).size();
  ASSERT_GT(new_size, old_bytes.size());

  std::vector<rlim_t> limits = {0, 1, 7, 8, 12, new_size - 4, new_size - 1};
  for (size_t k = 1; k < 40; ++k) limits.push_back(new_size * k / 40);
  for (const rlim_t limit : limits) {
    ASSERT_TRUE(saveFailsWithFileSizeLimit(new_map, path, limit)) << "limit " << limit;
    EXPECT_EQ(ndtom::encodeMap(ndtom::loadMap(path)), old_bytes) << "limit " << limit;
    EXPECT_EQ(leftoverTemporaries(path), 0) << "limit " << limit;
  }
  // Without a limit the same save goes through and replaces the file.
  ndtom::saveMap(new_map, path);
  EXPECT_EQ(ndtom::loadMap(path).numCells(), new_map.numCells());
  std::filesystem::remove(path);
}
