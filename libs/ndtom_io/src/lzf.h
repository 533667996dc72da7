// LZF decompression (the format of liblzf, used by PCD's binary_compressed data).
#pragma once

#include <cstddef>

namespace ndtom::io {

/// Decompresses exactly `out_size` bytes; false if the input is corrupt or sizes disagree.
bool lzfDecompress(const char* in, size_t in_size, char* out, size_t out_size);

}  // namespace ndtom::io
