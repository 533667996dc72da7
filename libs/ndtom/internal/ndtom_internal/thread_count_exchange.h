// The processes of a distributed build as threads of one program, trading counts through
// memory (count_exchange.h): for tests, and for ndtom-rank-model's measurements without MPI.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <vector>

#include "ndtom/partition/count_exchange.h"

namespace ndtom {

/// One per build; each of its `ranks` threads calls exchange() through its own port().
class ThreadCountExchange {
 public:
  explicit ThreadCountExchange(int ranks)
      : ranks_(ranks), posted_(size_t(ranks), nullptr), failed_(size_t(ranks), false) {
    ports_.reserve(size_t(ranks));  // port() hands out references
    for (int r = 0; r < ranks; ++r) ports_.emplace_back(*this, r);
  }
  ThreadCountExchange(const ThreadCountExchange&) = delete;
  ThreadCountExchange& operator=(const ThreadCountExchange&) = delete;

  CountExchange& port(int rank) { return ports_[size_t(rank)]; }

 private:
  class Port : public CountExchange {
   public:
    Port(ThreadCountExchange& hub, int rank) : hub_(&hub), rank_(rank) {}
    bool exchange(bool failed, const std::vector<std::vector<uint32_t>>& outgoing,
                  std::vector<std::vector<uint32_t>>& incoming) override {
      return hub_->exchange(rank_, failed, outgoing, incoming);
    }

   private:
    ThreadCountExchange* hub_;
    int rank_;
  };

  bool exchange(int rank, bool failed, const std::vector<std::vector<uint32_t>>& outgoing,
                std::vector<std::vector<uint32_t>>& incoming) {
    std::unique_lock<std::mutex> lock(mutex_);
    posted_[size_t(rank)] = &outgoing;
    failed_[size_t(rank)] = failed;
    arriveAndWait(lock);  // every thread has posted
    bool any_failed = false;
    for (const bool f : failed_) any_failed = any_failed || f;
    incoming.resize(size_t(ranks_));  // the messages' buffers kept from scan to scan
    for (std::vector<uint32_t>& words : incoming) words.clear();
    if (!any_failed)
      for (int r = 0; r < ranks_; ++r)
        if (r != rank) incoming[size_t(r)] = (*posted_[size_t(r)])[size_t(rank)];
    arriveAndWait(lock);  // every thread has read: the posted messages may go
    return !any_failed;
  }

  void arriveAndWait(std::unique_lock<std::mutex>& lock) {
    const uint64_t generation = generation_;
    if (++arrived_ == ranks_) {
      arrived_ = 0;
      ++generation_;
      all_arrived_.notify_all();
      return;
    }
    all_arrived_.wait(lock, [&] { return generation_ != generation; });
  }

  const int ranks_;
  std::mutex mutex_;
  std::condition_variable all_arrived_;
  int arrived_ = 0;
  uint64_t generation_ = 0;
  std::vector<const std::vector<std::vector<uint32_t>>*> posted_;
  std::vector<bool> failed_;
  std::vector<Port> ports_;
};

}  // namespace ndtom
