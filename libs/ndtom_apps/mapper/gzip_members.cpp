#include "ndtom_apps/gzip_members.h"

#include <libdeflate.h>

#include <algorithm>
#include <stdexcept>

namespace ndtom::mapper {
namespace {

// One gzip member (header, deflate stream, CRC-32 and size) of `size` bytes. libdeflate
// compresses a whole buffer in about half zlib's instructions at the fastest level.
std::string gzipMember(const char* data, size_t size, int level) {
  libdeflate_compressor* z = libdeflate_alloc_compressor(level);
  if (!z) throw std::runtime_error("gzip: cannot start libdeflate's compressor");
  std::string out(libdeflate_gzip_compress_bound(z, size), '\0');
  const size_t written = libdeflate_gzip_compress(z, data, size, out.data(), out.size());
  libdeflate_free_compressor(z);
  if (written == 0) throw std::runtime_error("gzip: libdeflate's compressor failed");
  out.resize(written);
  return out;
}

}  // namespace

GzipMemberWriter::GzipMemberWriter(const ndtom::FileSink& out, int level, int threads)
    : out_(out),
      level_(level),
      max_in_flight_(size_t(std::max(threads, 1))),
      part_(new char[kPartBytes]) {}

GzipMemberWriter::~GzipMemberWriter() {
  for (auto& f : in_flight_) f.wait();  // they own their parts, but must not outlive us
}

void GzipMemberWriter::writeAcrossParts(const void* data, size_t size) {
  const char* bytes = static_cast<const char*>(data);
  while (size > 0) {
    const size_t take = std::min(size, kPartBytes - fill_);
    std::memcpy(part_.get() + fill_, bytes, take);
    fill_ += take;
    bytes += take;
    size -= take;
    if (fill_ == kPartBytes) launchPart();
  }
}

void GzipMemberWriter::finish() {
  if (fill_ > 0 || !any_part_) launchPart();  // an empty input is one empty member
  while (!in_flight_.empty()) writeOldest();
}

void GzipMemberWriter::launchPart() {
  if (in_flight_.size() == max_in_flight_) writeOldest();
  std::shared_ptr<char[]> part(part_.release());
  const size_t size = fill_;
  part_.reset(new char[kPartBytes]);
  fill_ = 0;
  in_flight_.push_back(
      std::async(max_in_flight_ > 1 ? std::launch::async : std::launch::deferred,
                 [part, size, level = level_] { return gzipMember(part.get(), size, level); }));
  any_part_ = true;
}

void GzipMemberWriter::writeOldest() {
  const std::string member = in_flight_.front().get();
  in_flight_.pop_front();
  out_(member.data(), member.size());
}

}  // namespace ndtom::mapper
