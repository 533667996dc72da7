// The options of a map as one table: a row per option with its name, unit, type, bounds and
// description, and member pointers to where it lives in MapOptions. Validation, equality, the
// map file's option fields, the MRPT plugin's .ini keys and the programs' --help and flags
// all walk this table, so a new option is a row here plus the code that uses it.
//
// Defaults stay the member initialisers of MapOptions, written once: a row's default is its
// value in MapOptions{} (optionDefault).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>

#include "ndtom/map/options.h"

namespace ndtom {

enum class OptionType {
  Real,
  Integer,
  Bool,
  Enum,  ///< an integer 0 .. n-1 with a name for each value (OptionRow::names)
};

/// Map options shape the map and are stored in its file, in the table's order. Machine
/// options (threads, memory budget) are settings of the computer inserting scans: not
/// stored, and changing one does not make another map.
enum class OptionScope { Map, Machine };

/// The valid values: from min to max, each end open or closed.
struct OptionBounds {
  double min = 0, max = 0;
  bool min_open = false, max_open = false;

  bool contains(double v) const {
    return (min_open ? v > min : v >= min) && (max_open ? v < max : v <= max);
  }
};

struct OptionRow {
  /// As in map files and .ini files; on the command line "--" + name with '-' for '_'.
  const char* name;
  const char* unit;  ///< "" for none
  OptionType type;
  OptionScope scope;
  OptionBounds bounds;
  const char* description;  ///< a short phrase, for --help and .ini comments
  /// The value in `unit` (an Enum's index, a Bool's 0 or 1).
  double (*get)(const MapOptions&);
  /// Stores a value that checkOptionValue() accepts.
  void (*set)(MapOptions&, double);
  /// Enum: the spelling of each value (0, 1, ...) in .ini files and on the command line.
  std::array<const char*, 4> names = {};
};

namespace detail {

template <class T>
constexpr double toOptionValue(T v) {
  if constexpr (std::is_enum_v<T>)
    return double(static_cast<std::underlying_type_t<T>>(v));
  else
    return double(v);
}

template <class T>
T fromOptionValue(double v) {
  if constexpr (std::is_same_v<T, bool>)
    return v != 0;
  else if constexpr (std::is_enum_v<T>)
    return T(std::underlying_type_t<T>(v));
  else
    return T(v);
}

/// get and set of the field reached by a chain of member pointers from MapOptions.
// clang-format off
template <auto... Path>
struct OptionField {
  static double get(const MapOptions& o) { return toOptionValue((o .* ... .* Path)); }
  static void set(MapOptions& o, double v) {
    auto& field = (o .* ... .* Path);
    field = fromOptionValue<std::remove_reference_t<decltype(field)>>(v);
  }
};
// clang-format on

// The memory budget is bytes in MapOptions, megabytes (10^6 bytes) where people type it.
inline double memoryBudgetMb(const MapOptions& o) {
  return double(o.scan.memory_budget) / 1e6;
}
inline void setMemoryBudgetMb(MapOptions& o, double mb) {
  const double bytes = std::round(mb * 1e6);  // rounded: a value printed in MB reads back exact
  o.scan.memory_budget = bytes >= 18446744073709551615.0 ? UINT64_MAX : uint64_t(bytes);
}

}  // namespace detail

/// A row for the field at MapOptions .* Path.
template <auto... Path>
constexpr OptionRow optionRow(const char* name, const char* unit, OptionType type,
                              OptionScope scope, OptionBounds bounds, const char* description,
                              std::array<const char*, 4> names = {}) {
  using Field = detail::OptionField<Path...>;
  return {name, unit, type, scope, bounds, description, &Field::get, &Field::set, names};
}

/// A row whose value is converted on its way in and out of MapOptions (e.g. bytes as MB).
constexpr OptionRow convertedRow(const char* name, const char* unit, OptionType type,
                                 OptionScope scope, OptionBounds bounds, const char* description,
                                 double (*get)(const MapOptions&),
                                 void (*set)(MapOptions&, double)) {
  return {name, unit, type, scope, bounds, description, get, set};
}

inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// Every option of MapOptions. The Map-scope rows, in this order, are the option fields of
/// map files (map_io.h): their order and names must not change, or existing files would no
/// longer read back byte for byte.
inline constexpr std::array<OptionRow, 13> kMapOptionRows = {{
    optionRow<&MapOptions::resolution>("resolution", "m", OptionType::Real, OptionScope::Map,
                                       {kMinResolution, kMaxResolution}, "Cell edge"),
    optionRow<&MapOptions::occupancy, &OccupancyOptions::enabled>(
        "occupancy_enabled", "", OptionType::Bool, OptionScope::Map, {0, 1},
        "Occupancy by ray tracing (Eq. 12); false: Recursive NDT"),
    optionRow<&MapOptions::occupancy, &OccupancyOptions::p_hit>(
        "p_hit", "", OptionType::Real, OptionScope::Map, {0.5, 1, true, true},
        "p_o: occupancy of a cell with hits"),
    optionRow<&MapOptions::occupancy, &OccupancyOptions::p_miss>(
        "p_miss", "", OptionType::Real, OptionScope::Map, {0, 0.5, true, true},
        "p_e: occupancy of a cell a ray crosses"),
    optionRow<&MapOptions::occupancy, &OccupancyOptions::logodds_min>(
        "logodds_min", "", OptionType::Real, OptionScope::Map, {-kInf, 0, true, true},
        "Lower log-odds clamp"),
    optionRow<&MapOptions::occupancy, &OccupancyOptions::logodds_max>(
        "logodds_max", "", OptionType::Real, OptionScope::Map, {0, kInf, true, true},
        "Upper log-odds clamp"),
    optionRow<&MapOptions::scan, &ScanOptions::min_range>("min_range", "m", OptionType::Real,
                                                          OptionScope::Map, {0, kInf, false, true},
                                                          "Closer points are dropped"),
    optionRow<&MapOptions::scan, &ScanOptions::max_range>(
        "max_range", "m", OptionType::Real, OptionScope::Map, {0, kInf, true, false},
        "Farther points: free ray up to here, no hit (inf: no limit)"),
    optionRow<&MapOptions::scan, &ScanOptions::ray_mode>(
        "ray_mode", "", OptionType::Enum, OptionScope::Map, {0, 1},
        "One ray per point (PerPoint) or per hit cell (PerHitCell, faster)",
        {{"PerPoint", "PerHitCell"}}),
    optionRow<&MapOptions::regularization, &Regularization::min_eigen_ratio>(
        "min_eigen_ratio", "", OptionType::Real, OptionScope::Map, {0, 1},
        "Covariance eigenvalue floor, relative to the largest"),
    optionRow<&MapOptions::regularization, &Regularization::min_eigen_abs>(
        "min_eigen_abs", "m^2", OptionType::Real, OptionScope::Map, {0, kInf, false, true},
        "Covariance eigenvalue floor"),
    optionRow<&MapOptions::scan, &ScanOptions::threads>(
        "threads", "", OptionType::Integer, OptionScope::Machine, {1, ScanOptions::kMaxThreads},
        "Threads inserting a scan; the same map for any count"),
    convertedRow("memory_budget", "MB", OptionType::Real, OptionScope::Machine,
                 {1, kInf, false, true},
                 "Memory the map and a scan may take; larger scans are refused",
                 &detail::memoryBudgetMb, &detail::setMemoryBudgetMb),
}};

/// The row named `name`, or nullptr.
const OptionRow* findOptionRow(const std::string& name);

/// The row's value in MapOptions{}.
double optionDefault(const OptionRow& row);

/// Whether `value` is one of the row's type: any real but NaN, an integer (an Enum's index),
/// or exactly 0 or 1 for a Bool (not −0, which would not read back as itself).
bool isOfOptionType(const OptionRow& row, double value);

/// Throws std::invalid_argument("<name> = <value>: <why>") unless `value` is of the row's type
/// and within its bounds.
void checkOptionValue(const OptionRow& row, double value);

/// An Enum's names, "A or B" (", " before the last two for more).
std::string optionChoices(const OptionRow& row);

/// The value as .ini files and --help write it: an Enum by its name, a Bool as true/false.
std::string optionValueText(const OptionRow& row, double value);

/// The row of the first option of `scope` in which `a` and `b` differ, or nullptr.
const OptionRow* firstDifference(const MapOptions& a, const MapOptions& b, OptionScope scope);

/// Options of `scope` copied from `from` into `to`.
void copyOptions(const MapOptions& from, MapOptions& to, OptionScope scope);

/// Every option equal (machine options included).
bool operator==(const MapOptions& a, const MapOptions& b);
inline bool operator!=(const MapOptions& a, const MapOptions& b) {
  return !(a == b);
}

}  // namespace ndtom
