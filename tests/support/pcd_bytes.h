// PCD bytes made by hand for tests and the red team: a valid LZF stream, and the red team's
// header whose sizes multiply to 2^64 (issue #17).
#pragma once

#include <algorithm>
#include <string>

namespace ndtom::testing {

/// A valid LZF stream made of literal runs only (control byte = run length − 1 < 32).
inline std::string lzfLiterals(const std::string& raw) {
  std::string out;
  for (size_t i = 0; i < raw.size(); i += 32) {
    const size_t run = std::min<size_t>(32, raw.size() - i);
    out.push_back(char(run - 1));
    out.append(raw, i, run);
  }
  return out;
}

/// A binary_compressed PCD of 131,072 double fields of COUNT 2^20 and 2^24 points: 2^40
/// bytes a point, 2^64 in all (0 in 64 bits), with sizes 0 and 0 for its data.
inline std::string wrappingCompressedPcd() {
  std::string fields = "x y z", sizes = "8 8 8", types = "F F F",
              counts = "1048576 1048576 1048576";
  for (int i = 3; i < 131072; ++i) {
    fields += " f" + std::to_string(i);
    sizes += " 8";
    types += " F";
    counts += " 1048576";
  }
  return "FIELDS " + fields + "\nSIZE " + sizes + "\nTYPE " + types + "\nCOUNT " + counts +
         "\nWIDTH 16777216\nHEIGHT 1\nPOINTS 16777216\nDATA binary_compressed\n" +
         std::string(8, '\0');
}

/// Within the reader's field limits: 16 padding fields make a point 2^24 bytes, and 2^40
/// points make 2^64 bytes again.
inline std::string wideWrappingCompressedPcd() {
  std::string fields, sizes, types, counts;
  for (int i = 0; i < 16; ++i) {
    fields += " p" + std::to_string(i);
    sizes += " 1";
    types += " U";
    counts += i == 0 ? " 1048564" : " 1048576";  // 12 bytes less for x y z
  }
  return "FIELDS x y z" + fields + "\nSIZE 4 4 4" + sizes + "\nTYPE F F F" + types +
         "\nCOUNT 1 1 1" + counts +
         "\nWIDTH 1099511627776\nHEIGHT 1\nPOINTS 1099511627776\nDATA binary_compressed\n" +
         std::string(8, '\0');
}

}  // namespace ndtom::testing
