#include "scan_feed.h"

#include <array>
#include <stdexcept>

#include "mpi_pieces.h"

namespace ndtom::mapper {
namespace {

// What a scan is besides its points, as doubles: origin, frame pose (4x4), time, point count,
// the length of its name (sent next, so that every process's messages name the file).
constexpr int kHeader = 3 + 16 + 1 + 1 + 1;

void broadcast(void* data, uint64_t bytes, MPI_Comm comm) {
  auto* p = static_cast<char*>(data);
  forEachMpiPiece(bytes,
                  [&](uint64_t offset, int n) { MPI_Bcast(p + offset, n, MPI_BYTE, 0, comm); });
}

}  // namespace

ScanFeed::ScanFeed(ScanInput mode, std::unique_ptr<apps::ScanSource> source, MPI_Comm comm)
    : mode_(mode), source_(std::move(source)), comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  if (!source_ && (mode_ == ScanInput::EachReads || rank_ == 0))
    throw std::logic_error("ScanFeed: no scan source");
}

std::optional<apps::Scan> ScanFeed::next() {
  if (mode_ == ScanInput::EachReads) return source_->next();
  std::optional<apps::Scan> scan;
  std::array<double, kHeader> header{};
  int more = 0;
  if (rank_ == 0) {
    scan = source_->next();
    more = scan.has_value();
  }
  MPI_Bcast(&more, 1, MPI_INT, 0, comm_);
  if (!more) return std::nullopt;
  if (rank_ == 0) {
    for (int a = 0; a < 3; ++a) header[size_t(a)] = scan->sensor_origin[a];
    Eigen::Map<Eigen::Matrix4d>(header.data() + 3) = scan->frame_pose.matrix();
    header[19] = scan->time;
    header[20] = double(scan->points_world.size());
    header[21] = double(scan->name.size());
  }
  MPI_Bcast(header.data(), kHeader, MPI_DOUBLE, 0, comm_);
  if (rank_ != 0) {
    scan.emplace();
    scan->sensor_origin = Eigen::Vector3d(header[0], header[1], header[2]);
    scan->frame_pose.matrix() = Eigen::Map<const Eigen::Matrix4d>(header.data() + 3);
    scan->time = header[19];
    scan->points_world.resize(size_t(header[20]));
    scan->name.resize(size_t(header[21]));
  }
  broadcast(scan->name.data(), scan->name.size(), comm_);
  const uint64_t bytes = scan->points_world.size() * sizeof(Eigen::Vector3d);
  broadcast(scan->points_world.data(), bytes, comm_);
  bytes_ += bytes + scan->name.size() + sizeof(header) + sizeof(more);
  return scan;
}

}  // namespace ndtom::mapper
