#include "gzip_members.h"

#include <zlib.h>

#include <algorithm>
#include <stdexcept>

namespace ndtom::mapper {
namespace {

std::string gzipMember(const std::string& data, int level) {
  z_stream z{};
  // windowBits 15 + 16: a gzip header and trailer instead of zlib's.
  if (deflateInit2(&z, level, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("gzip: cannot start zlib's compressor");
  std::string out(deflateBound(&z, uLong(data.size())), '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  z.avail_in = uInt(data.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = uInt(out.size());
  const int status = deflate(&z, Z_FINISH);
  const size_t written = z.total_out;
  deflateEnd(&z);
  if (status != Z_STREAM_END) throw std::runtime_error("gzip: zlib's compressor failed");
  out.resize(written);
  return out;
}

}  // namespace

GzipMemberWriter::GzipMemberWriter(const ndtom::FileSink& out, int level, int threads)
    : out_(out), level_(level), max_in_flight_(size_t(std::max(threads, 1))) {
  part_.reserve(kPartBytes);
}

GzipMemberWriter::~GzipMemberWriter() {
  for (auto& f : in_flight_) f.wait();  // they read nothing of ours, but must not outlive us
}

void GzipMemberWriter::write(const void* data, size_t size) {
  const char* bytes = static_cast<const char*>(data);
  while (size > 0) {
    const size_t take = std::min(size, kPartBytes - part_.size());
    part_.append(bytes, take);
    bytes += take;
    size -= take;
    if (part_.size() == kPartBytes) launchPart();
  }
}

void GzipMemberWriter::finish() {
  if (!part_.empty() || !any_part_) launchPart();  // an empty input is one empty member
  while (!in_flight_.empty()) writeOldest();
}

void GzipMemberWriter::launchPart() {
  if (in_flight_.size() == max_in_flight_) writeOldest();
  std::string part;
  part.swap(part_);
  part_.reserve(kPartBytes);
  in_flight_.push_back(std::async(max_in_flight_ > 1 ? std::launch::async : std::launch::deferred,
                                  [p = std::move(part), level = level_] { return gzipMember(p, level); }));
  any_part_ = true;
}

void GzipMemberWriter::writeOldest() {
  const std::string member = in_flight_.front().get();
  in_flight_.pop_front();
  out_(member.data(), member.size());
}

}  // namespace ndtom::mapper
