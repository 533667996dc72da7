#include "ndtom_apps/csv_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace ndtom::apps {

CsvCell::CsvCell(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.10g", v);
  text = buffer;
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

void CsvTable::write(const std::string& path) const {
  std::ofstream out(path);
  auto writeLine = [&](const std::vector<std::string>& fields) {
    for (size_t i = 0; i < fields.size(); ++i) out << (i ? "," : "") << fields[i];
    out << '\n';
  };
  writeLine(columns_);
  for (const auto& row : rows_) writeLine(row);
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path);
}

}  // namespace ndtom::apps
