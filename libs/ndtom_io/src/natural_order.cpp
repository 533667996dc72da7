#include "ndtom_io/natural_order.h"

#include <cctype>

namespace ndtom::io {
namespace {

bool isDigit(char c) {
  return std::isdigit(static_cast<unsigned char>(c)) != 0;
}

// Compares the digit runs starting at a[i] and b[j] by value; advances i and j past them.
int compareNumbers(const std::string& a, size_t& i, const std::string& b, size_t& j) {
  while (i < a.size() && a[i] == '0') ++i;
  while (j < b.size() && b[j] == '0') ++j;
  const size_t start_a = i, start_b = j;
  while (i < a.size() && isDigit(a[i])) ++i;
  while (j < b.size() && isDigit(b[j])) ++j;
  const size_t len_a = i - start_a, len_b = j - start_b;
  if (len_a != len_b) return len_a < len_b ? -1 : 1;  // no leading zeros: longer is larger
  const int c = a.compare(start_a, len_a, b, start_b, len_b);
  return c < 0 ? -1 : (c > 0 ? 1 : 0);
}

}  // namespace

bool naturalLess(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (isDigit(a[i]) && isDigit(b[j])) {
      const int c = compareNumbers(a, i, b, j);
      if (c != 0) return c < 0;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  if (i < a.size() || j < b.size()) return j < b.size();  // the prefix comes first
  return a < b;
}

}  // namespace ndtom::io
