// A small table written as CSV: header line, then one line per row; numbers with 10
// significant digits.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ndtom::apps {

/// One CSV field, from text or a number.
struct CsvCell {
  std::string text;
  CsvCell(const char* s) : text(s) {}
  CsvCell(std::string s) : text(std::move(s)) {}
  CsvCell(double v);
  CsvCell(int v) : text(std::to_string(v)) {}
  CsvCell(int64_t v) : text(std::to_string(v)) {}
  CsvCell(size_t v) : text(std::to_string(v)) {}
  /// `v` in a printf format of one double ("%.6f", "%g"), for columns with a set precision.
  static CsvCell formatted(const char* format, double v);
};

class CsvTable {
 public:
  explicit CsvTable(std::vector<std::string> columns) : columns_(std::move(columns)) {}

  /// Throws std::logic_error if the row's width differs from the header's.
  void addRow(const std::vector<CsvCell>& cells);
  /// The numbers of one column; throws std::logic_error for an unknown name, and NaN for
  /// fields that are not numbers.
  std::vector<double> column(const std::string& name) const;
  size_t numRows() const { return rows_.size(); }
  /// The file's content.
  std::string text() const;
  /// Writes the file; throws std::runtime_error naming the path and the reason if it cannot be
  /// written whole (no folder, a full disk, ...).
  void write(const std::string& path) const;

 private:
  std::vector<std::string> columns_;
  std::vector<std::vector<std::string>> rows_;
};

}  // namespace ndtom::apps
