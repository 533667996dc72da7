// ndtom-worldgen: a city and a lidar drive through it, written as a folder of scans with
// poses, so that mapping, localization and distributed builds can be tested at the scale of
// kilometres without downloading data. Exit 0 on success, 1 for a failed write, 2 for a bad
// command line (also a run over the memory budget, the scan limit or the disk's free space,
// refused before anything is written).
//
// Scans are made a batch at a time and written as they are made: memory does not grow with
// the drive's length. They go into OUT/.ndtom-tmp-PID and move into OUT once all are written,
// poses.txt last (a folder with poses.txt is complete): a failed run leaves no scan behind,
// and a killed run's folder is removed by the next run in OUT.
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <thread>

#include "city_route.h"
#include "ndtom_apps/option_values.h"
#include "ndtom_apps/process_clock.h"
#include "ndtom_apps/progress.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_internal/atomic_file.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"
#include "simulated_lidar.h"
#include "world_options.h"

namespace {

using namespace ndtom::world;
namespace fs = std::filesystem;

constexpr size_t kBatch = 1024;  // poses simulated between two writes of poses.txt

std::string scanName(size_t i) {
  char name[32];
  std::snprintf(name, sizeof name, "scan%06zu.pcd", i);
  return name;
}

// OUT/.ndtom-tmp-PID, where a run's files are written before they move into OUT; removed
// with what is left in it when the run ends. Removes those of runs whose process is gone.
class StagingFolder {
 public:
  explicit StagingFolder(const fs::path& out) {
    const std::string marker = ndtom::kTemporaryMarker;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(out, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind(marker, 0) != 0) continue;
      const std::string digits = name.substr(marker.size());
      if (digits.empty() || digits.size() > 9 ||
          digits.find_first_not_of("0123456789") != std::string::npos)
        continue;
      if (::kill(pid_t(std::stol(digits)), 0) != 0 && errno == ESRCH)
        fs::remove_all(entry.path(), ec);
    }
    path_ = out / (marker + std::to_string(::getpid()));
    fs::remove_all(path_, ec);
    if (!fs::create_directory(path_, ec))
      throw std::runtime_error("cannot write in " + out.string() + ": " + ec.message());
  }
  ~StagingFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  StagingFolder(const StagingFolder&) = delete;
  StagingFolder& operator=(const StagingFolder&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// A text file written piece by piece; throws naming `name` when a write fails.
class TextFile {
 public:
  TextFile(const fs::path& path, std::string name) : name_(std::move(name)) {
    file_ = std::fopen(path.c_str(), "wb");
    if (!file_) fail(errno);
  }
  ~TextFile() {
    if (file_) std::fclose(file_);
  }
  void write(const std::string& text) {
    if (std::fwrite(text.data(), 1, text.size(), file_) != text.size()) fail(errno);
  }
  void close() {  // flushed to disk
    int err = 0;
    if (std::fflush(file_) != 0 || ::fsync(fileno(file_)) != 0) err = errno;
    if (std::fclose(file_) != 0 && err == 0) err = errno;
    file_ = nullptr;
    if (err != 0) fail(err);
  }

 private:
  [[noreturn]] void fail(int err) {
    throw std::runtime_error("cannot write " + name_ + ": " + std::strerror(err ? err : EIO));
  }
  std::string name_;
  std::FILE* file_ = nullptr;
};

int run(const WorldOptions& o) {
  checkDiskSpace(o);
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (!fs::is_directory(o.out)) throw ndtom::apps::UsageError(o.out + ": cannot create the folder");
  const auto start = std::chrono::steady_clock::now();
  const fs::path out(o.out);
  const StagingFolder staging(out);
  const CityWorld city(o.city);
  Drive drive(city, o.route);
  TextFile poses_file(staging.path() / "poses.txt", (out / "poses.txt").string());
  TextFile times_file(staging.path() / "times.txt", (out / "times.txt").string());

  // A batch of scans in parallel, each thread taking the next index: files are the same for
  // any count.
  ndtom::apps::Progress progress(!o.quiet);
  progress.start("", drive.size());
  size_t scans = 0;
  std::atomic<size_t> points{0}, done{0};
  std::vector<Eigen::Isometry3d> batch;
  batch.reserve(kBatch);
  for (;;) {
    batch.clear();
    for (Eigen::Isometry3d pose; batch.size() < kBatch && drive.next(pose);) batch.push_back(pose);
    if (batch.empty()) break;
    std::atomic<size_t> next{0};
    std::exception_ptr failure;
    std::mutex report;
    const auto work = [&] {
      for (size_t i; (i = next++) < batch.size();) {
        try {
          const auto scan = simulateScan(city, o.lidar, batch[i], scans + i);
          try {
            ndtom::io::writePcdBinary((staging.path() / scanName(scans + i)).string(), scan);
          } catch (const std::runtime_error& e) {  // named by its temporary: name the output
            throw std::runtime_error((out / scanName(scans + i)).string() + ": " + e.what());
          }
          points += scan.size();
        } catch (...) {
          std::lock_guard<std::mutex> lock(report);
          if (!failure) failure = std::current_exception();
          next = batch.size();
          return;
        }
        std::lock_guard<std::mutex> lock(report);
        progress.update(++done, points);
      }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < o.threads && size_t(t) < batch.size(); ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
    poses_file.write(ndtom::io::kittiPoseText(batch));
    std::string times;
    char line[64];
    for (size_t i = 0; i < batch.size(); ++i) {
      std::snprintf(line, sizeof line, "%.6f\n", double(scans + i) * o.route.step / o.speed);
      times += line;
    }
    times_file.write(times);
    scans += batch.size();
  }
  poses_file.close();
  times_file.close();
  // Into place: the previous poses.txt first (the folder is incomplete until the new one is
  // in), poses.txt last.
  fs::remove(out / "poses.txt", ec);
  for (size_t i = 0; i < scans; ++i)
    ndtom::renameFile((staging.path() / scanName(i)).string(), (out / scanName(i)).string());
  ndtom::renameFile((staging.path() / "times.txt").string(), (out / "times.txt").string());
  ndtom::renameFile((staging.path() / "poses.txt").string(), (out / "poses.txt").string());
  if (!o.quiet)
    std::printf(
        "ndtom-worldgen: %zu scans over %.2f km in a city of %dx%d blocks (%zu boxes), "
        "%.1f M points, %.1f s; wrote %s\n",
        scans, o.route.length / 1000, o.city.blocks_x, o.city.blocks_y, city.boxes().size(),
        double(points) / 1e6, ndtom::apps::secondsSince(start), o.out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return ndtom::apps::runProgram("ndtom-worldgen", [&] {
    const WorldOptions options = parseWorldOptions(argc, argv);
    if (options.help) {
      std::fputs(worldHelpText().c_str(), stdout);
      return 0;
    }
    return run(options);
  });
}
