// The count exchange of a distributed build whose processes share the rays out
// (count_exchange.h), over MPI: one all-reduce of the failure flag, one all-to-all of the
// message sizes and one of the messages, per scan.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <vector>

#include "ndtom/partition/count_exchange.h"

namespace ndtom::mapper {

class MpiCountExchange : public CountExchange {
 public:
  explicit MpiCountExchange(MPI_Comm comm);
  bool exchange(bool failed, const std::vector<std::vector<uint32_t>>& outgoing,
                std::vector<std::vector<uint32_t>>& incoming) override;
  uint64_t bytesSent() const { return bytes_sent_; }  ///< counts, over all scans

 private:
  MPI_Comm comm_;
  int rank_ = 0, ranks_ = 1;
  uint64_t bytes_sent_ = 0;
  std::vector<uint32_t> send_, receive_;  // the messages end to end, kept from scan to scan
};

}  // namespace ndtom::mapper
