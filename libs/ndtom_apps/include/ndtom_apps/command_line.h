// The command lines of the programs: "--flag" alone or "--option VALUE", strictly, and the
// systems, modes, ... a program names in a list ("--systems a,b").
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ndtom_apps/option_values.h"

namespace ndtom::apps {

/// Walks argv[1..argc-1]: `flag(name)` for each argument listed in `flags`, else
/// `option(name, value)` with the argument after it. Throws UsageError
/// "NAME: missing value (see --help)" when none follows; the callbacks throw UsageError for
/// names they do not know.
void forEachArgument(
    int argc, const char* const argv[], const std::vector<std::string>& flags,
    const std::function<void(const std::string& name)>& flag,
    const std::function<void(const std::string& name, const std::string& value)>& option);

/// Options from a command line of "--option VALUE" pairs (forEachArgument's rules) and the
/// flags --help, -h and --quiet, which set `help` and `quiet`; `set(options, name, value)`
/// takes each option.
template <typename Options, typename Set>
Options parseOptionPairs(int argc, const char* const argv[], const Set& set) {
  Options o;
  forEachArgument(
      argc, argv, {"--help", "-h", "--quiet"},
      [&](const std::string& flag) { (flag == "--quiet" ? o.quiet : o.help) = true; },
      [&](const std::string& name, const std::string& value) { set(o, name, value); });
  return o;
}

/// One argument of a command line in the style of ndtom-map: an option with its value (empty
/// for a flag) or a positional argument (name empty).
struct Argument {
  std::string name;
  std::string value;
  bool positional() const { return name.empty(); }
};

/// Splits argv[1..argc-1] into arguments: "--name=value", "--name value", "-o value", a flag
/// "--name", or a positional argument ("-" and "" included). `takes_value(name)` says whether
/// an option takes a value, std::nullopt for names the program does not know. Throws
/// UsageError "NAME: unknown option (see --help)", "NAME: takes no value" or
/// "NAME: missing value".
std::vector<Argument> splitArguments(
    int argc, const char* const argv[],
    const std::function<std::optional<bool>(const std::string& name)>& takes_value);

/// An option of a program whose command line is a table: whether it takes a value, and how
/// it sets it in the program's options.
template <typename Options>
struct OptionSpec {
  bool takes_value;
  std::function<void(Options&, const std::string& value)> handle;
};

template <typename Options>
using OptionTable = std::map<std::string, OptionSpec<Options>>;

/// `table` and --help, -h, --quiet, -q, which set `help` and `quiet` in any program's options.
template <typename Options>
OptionTable<Options> withHelpAndQuiet(OptionTable<Options> table) {
  const auto help = [](Options& o, const std::string&) { o.help = true; };
  const auto quiet = [](Options& o, const std::string&) { o.quiet = true; };
  for (const char* name : {"--help", "-h"}) table[name] = {false, help};
  for (const char* name : {"--quiet", "-q"}) table[name] = {false, quiet};
  return table;
}

/// Sets `options` from argv[1..argc-1] through `table` (splitArguments' rules) and returns the
/// positional arguments in order.
template <typename Options>
std::vector<std::string> applyArguments(int argc, const char* const argv[],
                                        const OptionTable<Options>& table, Options& options) {
  const auto takes_value = [&](const std::string& name) -> std::optional<bool> {
    const auto spec = table.find(name);
    if (spec == table.end()) return std::nullopt;
    return spec->second.takes_value;
  };
  std::vector<std::string> positional;
  for (const Argument& a : splitArguments(argc, argv, takes_value)) {
    if (a.positional())
      positional.push_back(a.value);
    else
      table.at(a.name).handle(options, a.value);
  }
  return positional;
}

/// The UsageError for an argument no program option has: "unknown option 'NAME' (see --help)".
UsageError unknownOption(const std::string& name);

/// One name a list option accepts and what it stands for.
template <typename T>
struct NamedValue {
  const char* name;
  T value;
};

/// The values a comma-separated list names, in its order. Throws UsageError for a name not in
/// `table`, a name given twice, or an empty list.
template <typename T, size_t N>
std::vector<T> parseNamedList(const std::string& option, const std::string& text,
                              const NamedValue<T> (&table)[N]) {
  std::vector<T> out;
  for (const std::string& item : splitList(text)) {
    const auto* named = std::find_if(std::begin(table), std::end(table),
                                     [&](const NamedValue<T>& n) { return item == n.name; });
    if (named == std::end(table))
      throw UsageError(option + ": unknown name '" + item + "' (see --help)");
    if (std::find(out.begin(), out.end(), named->value) != out.end())
      throw UsageError(option + ": " + item + " is listed twice");
    out.push_back(named->value);
  }
  if (out.empty()) throw UsageError(option + ": empty list");
  return out;
}

/// The name of `value` in `table`; "?" if it has none.
template <typename T, size_t N>
const char* nameOf(T value, const NamedValue<T> (&table)[N]) {
  for (const NamedValue<T>& n : table)
    if (n.value == value) return n.name;
  return "?";
}

}  // namespace ndtom::apps
