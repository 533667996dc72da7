#include "lzf.h"

#include <cstdint>

namespace ndtom::io {

// Each control byte starts either a literal run (ctrl < 32: ctrl + 1 bytes follow) or a
// back-reference (length ctrl >> 5, extended by one byte when 7; offset from 13 bits).
bool lzfDecompress(const char* in, size_t in_size, char* out, size_t out_size) {
  const auto* ip = reinterpret_cast<const uint8_t*>(in);
  const uint8_t* const in_end = ip + in_size;
  auto* op = reinterpret_cast<uint8_t*>(out);
  uint8_t* const out_begin = op;
  uint8_t* const out_end = op + out_size;
  while (ip < in_end) {
    size_t ctrl = *ip++;
    if (ctrl < 32) {
      const size_t run = ctrl + 1;
      if (size_t(in_end - ip) < run || size_t(out_end - op) < run) return false;
      for (size_t i = 0; i < run; ++i) *op++ = *ip++;
    } else {
      size_t len = ctrl >> 5;
      if (len == 7) {
        if (ip >= in_end) return false;
        len += *ip++;
      }
      if (ip >= in_end) return false;
      const size_t back = ((ctrl & 0x1f) << 8) + *ip++ + 1;
      len += 2;
      if (size_t(op - out_begin) < back || size_t(out_end - op) < len) return false;
      const uint8_t* ref = op - back;
      for (size_t i = 0; i < len; ++i) *op++ = *ref++;  // may overlap: byte by byte
    }
  }
  return op == out_end;
}

}  // namespace ndtom::io
