#include "mpi_count_exchange.h"

#include <climits>
#include <stdexcept>
#include <string>

namespace ndtom::mapper {

MpiCountExchange::MpiCountExchange(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &ranks_);
}

bool MpiCountExchange::exchange(bool failed, const std::vector<std::vector<uint32_t>>& outgoing,
                                std::vector<std::vector<uint32_t>>& incoming) {
  int any_failed = failed ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &any_failed, 1, MPI_INT, MPI_MAX, comm_);
  const size_t ranks = size_t(ranks_);
  incoming.resize(ranks);  // the messages' buffers kept from scan to scan
  for (std::vector<uint32_t>& words : incoming) words.clear();
  if (any_failed) return false;
  if (outgoing.size() != ranks) throw std::logic_error("MpiCountExchange: a message per process");
  // MPI counts are ints: a scan's counts fit unless they span ~10^7 blocks.
  auto checkFits = [](size_t words, const char* direction) {
    if (words > size_t(INT_MAX))
      throw std::runtime_error(std::string("ndtom-map-mpi: one scan's counts ") + direction +
                               " the other processes pass 2^31 words; use fewer, larger "
                               "processes or --ray-share tiles");
  };
  std::vector<int> send_counts(ranks), send_offsets(ranks), receive_counts(ranks),
      receive_offsets(ranks);
  size_t total = 0;
  for (size_t r = 0; r < ranks; ++r) {
    checkFits(total + outgoing[r].size(), "for");
    send_counts[r] = int(outgoing[r].size());
    send_offsets[r] = int(total);
    total += outgoing[r].size();
  }
  send_.resize(total);
  for (size_t r = 0; r < ranks; ++r)
    std::copy(outgoing[r].begin(), outgoing[r].end(), send_.begin() + send_offsets[r]);
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, comm_);
  size_t received = 0;
  for (size_t r = 0; r < ranks; ++r) {
    checkFits(received + size_t(receive_counts[r]), "from");
    receive_offsets[r] = int(received);
    received += size_t(receive_counts[r]);
  }
  receive_.resize(received);
  MPI_Alltoallv(send_.data(), send_counts.data(), send_offsets.data(), MPI_UINT32_T,
                receive_.data(), receive_counts.data(), receive_offsets.data(), MPI_UINT32_T,
                comm_);
  for (size_t r = 0; r < ranks; ++r)
    incoming[r].assign(receive_.begin() + receive_offsets[r],
                       receive_.begin() + receive_offsets[r] + receive_counts[r]);
  bytes_sent_ += (total - outgoing[size_t(rank_)].size()) * sizeof(uint32_t);
  return true;
}

}  // namespace ndtom::mapper
