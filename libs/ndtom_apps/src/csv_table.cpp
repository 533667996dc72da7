#include "ndtom_apps/csv_table.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace ndtom::apps {

CsvCell::CsvCell(double v) : CsvCell(formatted("%.10g", v)) {}

CsvCell CsvCell::formatted(const char* format, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, v);
  return CsvCell(std::string(buffer));
}

void CsvTable::addRow(const std::vector<CsvCell>& cells) {
  if (cells.size() != columns_.size())
    throw std::logic_error("CSV row has " + std::to_string(cells.size()) + " fields, header " +
                           std::to_string(columns_.size()));
  std::vector<std::string> row;
  row.reserve(cells.size());
  for (const CsvCell& c : cells) row.push_back(c.text);
  rows_.push_back(std::move(row));
}

std::vector<double> CsvTable::column(const std::string& name) const {
  const auto it = std::find(columns_.begin(), columns_.end(), name);
  if (it == columns_.end()) throw std::logic_error("CSV table has no column " + name);
  const size_t index = size_t(it - columns_.begin());
  std::vector<double> values;
  values.reserve(rows_.size());
  for (const auto& row : rows_) {
    char* end = nullptr;
    const double v = std::strtod(row[index].c_str(), &end);
    values.push_back(end && *end == '\0' && end != row[index].c_str() ? v : NAN);
  }
  return values;
}

std::string CsvTable::text() const {
  std::string out;
  auto addLine = [&](const std::vector<std::string>& fields) {
    for (size_t i = 0; i < fields.size(); ++i) (out += i ? "," : "") += fields[i];
    out += '\n';
  };
  addLine(columns_);
  for (const auto& row : rows_) addLine(row);
  return out;
}

void CsvTable::write(const std::string& path) const {
  errno = 0;
  std::ofstream out(path, std::ios::binary);
  out << text();
  out.close();  // flushes: a full disk shows here
  if (!out)
    throw std::runtime_error("cannot write " + path +
                             (errno ? std::string(": ") + std::strerror(errno) : std::string()));
}

}  // namespace ndtom::apps
