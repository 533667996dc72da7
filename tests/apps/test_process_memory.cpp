// keepFreedHeapForReuse: a buffer freed and allocated again is not faulted in again (counted by
// the kernel's minor page faults), while without it glibc maps and unmaps such a buffer.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstdlib>
#include <cstring>

#include "ndtom_apps/process_memory.h"

namespace {

long minorFaults() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}

/// Minor faults of allocating, touching and freeing `bytes`, the second time in a row.
long faultsOfReallocating(size_t bytes) {
  for (int round = 0;; ++round) {
    const long before = minorFaults();
    auto* p = static_cast<char*>(std::malloc(bytes));
    std::memset(p, 1, bytes);
    asm volatile("" : : "r"(p) : "memory");  // the writes happen
    std::free(p);
    if (round == 1) return minorFaults() - before;
  }
}

bool underSanitizer() {
#if defined(__SANITIZE_ADDRESS__)
  return true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  return true;
#endif
#endif
  return false;
}

TEST(ProcessMemory, FreedBuffersAreReusedWithoutPageFaults) {
  if (underSanitizer()) GTEST_SKIP() << "the sanitizer's allocator ignores mallopt";
  constexpr size_t kBytes = 24 << 20;  // above glibc's default mmap threshold, below 32 MB
  const long pages = long(kBytes / 4096);
  // Without the setting (a fresh process: the threshold has not adapted to this size yet),
  // the buffer is mapped anew and every page faults.
  EXPECT_GT(faultsOfReallocating(kBytes), pages / 2);
  ndtom::apps::keepFreedHeapForReuse();
  faultsOfReallocating(kBytes);  // the heap grows to hold it once
  EXPECT_LT(faultsOfReallocating(kBytes), pages / 20);
}

}  // namespace
