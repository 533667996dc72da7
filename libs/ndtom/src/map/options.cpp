#include "ndtom/map/options.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "ndtom/map/option_table.h"
#include "support/option_error.h"

namespace ndtom {
namespace {

std::string interval(const OptionBounds& b) {
  std::ostringstream s;
  s << (b.min_open ? '(' : '[') << b.min << ", " << b.max << (b.max_open ? ')' : ']');
  return s.str();
}

size_t enumCount(const OptionRow& row) {
  size_t n = 0;
  while (n < row.names.size() && row.names[n]) ++n;
  return n;
}

// Every row checked on `o`; a sub-struct is validated inside default options, which are valid,
// so only its own fields can fail.
void validateRows(const MapOptions& o) {
  for (const OptionRow& row : kMapOptionRows) checkOptionValue(row, row.get(o));
}

}  // namespace

const char* toString(RayMode mode) {
  switch (mode) {
    case RayMode::PerPoint:
      return "per_point";
    case RayMode::PerHitCell:
      return "per_hit_cell";
  }
  return "unknown";
}

RayMode rayModeFromString(const std::string& text) {
  if (text == "per_point" || text == "PerPoint" || text == "0") return RayMode::PerPoint;
  if (text == "per_hit_cell" || text == "PerHitCell" || text == "1") return RayMode::PerHitCell;
  throw std::invalid_argument("ray_mode = " + text + ": expected per_point or per_hit_cell");
}

double OccupancyOptions::hitLogOdds() const {
  return std::log(p_hit / (1.0 - p_hit));
}
double OccupancyOptions::missLogOdds() const {
  return std::log(p_miss / (1.0 - p_miss));
}

const OptionRow* findOptionRow(const std::string& name) {
  for (const OptionRow& row : kMapOptionRows)
    if (name == row.name) return &row;
  return nullptr;
}

double optionDefault(const OptionRow& row) {
  return row.get(MapOptions());
}

bool isOfOptionType(const OptionRow& row, double value) {
  switch (row.type) {
    case OptionType::Real:
      return !std::isnan(value);
    case OptionType::Integer:
      return std::isfinite(value) && value == std::floor(value) &&
             !(value == 0 && std::signbit(value));
    case OptionType::Bool:
      return (value == 0.0 && !std::signbit(value)) || value == 1.0;
    case OptionType::Enum:
      return (value == 0.0 && !std::signbit(value)) ||
             (value == std::floor(value) && value >= 1 && value < double(enumCount(row)));
  }
  return false;
}

void checkOptionValue(const OptionRow& row, double value) {
  if (row.type == OptionType::Bool && !isOfOptionType(row, value))
    failOption(row.name, value, "must be 0 or 1");
  if (row.type == OptionType::Enum && !isOfOptionType(row, value))
    failOption(row.name, value, ("must be " + optionChoices(row) + " (or its number)").c_str());
  if (!isOfOptionType(row, value) || !row.bounds.contains(value)) {
    std::string why = std::string("must be ") +
                      (row.type == OptionType::Integer ? "an integer in " : "in ") +
                      interval(row.bounds);
    if (*row.unit) why += std::string(" ") + row.unit;
    failOption(row.name, value, why.c_str());
  }
}

std::string optionChoices(const OptionRow& row) {
  const size_t n = enumCount(row);
  std::string text;
  for (size_t i = 0; i < n; ++i)
    text += std::string(i == 0 ? "" : i + 1 == n ? " or " : ", ") + row.names[i];
  return text;
}

std::string optionValueText(const OptionRow& row, double value) {
  if (row.type == OptionType::Bool) return value != 0 ? "true" : "false";
  if (row.type == OptionType::Enum && isOfOptionType(row, value)) return row.names[size_t(value)];
  std::ostringstream s;
  s << value;
  return s.str();
}

const OptionRow* firstDifference(const MapOptions& a, const MapOptions& b, OptionScope scope) {
  for (const OptionRow& row : kMapOptionRows)
    if (row.scope == scope && !(row.get(a) == row.get(b))) return &row;
  return nullptr;
}

void copyOptions(const MapOptions& from, MapOptions& to, OptionScope scope) {
  for (const OptionRow& row : kMapOptionRows)
    if (row.scope == scope) row.set(to, row.get(from));
}

bool operator==(const MapOptions& a, const MapOptions& b) {
  return !firstDifference(a, b, OptionScope::Map) && !firstDifference(a, b, OptionScope::Machine);
}

void validate(const OccupancyOptions& o) {
  MapOptions m;
  m.occupancy = o;
  validateRows(m);
}

void validate(const ScanOptions& o) {
  MapOptions m;
  m.scan = o;
  validateRows(m);
  if (!(o.max_range > o.min_range)) failOption("max_range", o.max_range, "must be > min_range");
}

void validate(const Regularization& r) {
  MapOptions m;
  m.regularization = r;
  validateRows(m);
}

void validate(const MapOptions& o) {
  validateRows(o);
  if (!(o.scan.max_range > o.scan.min_range))
    failOption("max_range", o.scan.max_range, "must be > min_range");
  // A floor above r² makes every Gaussian wider than its cell: a map of blobs, and pictures
  // whose ellipses each cover the picture.
  const double cell_area = o.resolution * o.resolution;
  if (!(o.regularization.min_eigen_abs <= cell_area))
    failOption("min_eigen_abs", o.regularization.min_eigen_abs,
               ("must be <= resolution^2 (" + std::to_string(cell_area) + " m^2)").c_str());
}

}  // namespace ndtom
