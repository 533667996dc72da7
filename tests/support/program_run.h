// Running one of the programs from a test, and reading back what it wrote: its exit status,
// stdout and stderr (through files in a folder of the test's), and its CSV tables.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace ndtom::testing {

struct ProgramRun {
  int exit_code = -1;
  std::string stdout_text, stderr_text;
};

inline std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Runs `exe ARGS` (arguments already quoted as needed) with stdin empty; stdout and stderr
/// pass through files in `dir`.
inline ProgramRun runProgram(const std::string& exe, const std::string& args,
                             const std::filesystem::path& dir) {
  const std::filesystem::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string command =
      "'" + exe + "' " + args + " >'" + out.string() + "' 2>'" + err.string() + "' </dev/null";
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readFile(out), readFile(err)};
}

/// The fields of one CSV line; empty fields are kept ("a,,b," has four).
inline std::vector<std::string> csvFields(const std::string& line) {
  std::vector<std::string> fields(1);
  for (char c : line) {
    if (c == ',')
      fields.emplace_back();
    else
      fields.back() += c;
  }
  return fields;
}

using CsvRow = std::map<std::string, std::string>;

/// A CSV file as its header and rows keyed by column; a row whose width differs from the
/// header's fails the test that reads it.
struct Csv {
  std::vector<std::string> columns;
  std::vector<CsvRow> rows;

  double number(size_t row, const std::string& column) const {
    return std::stod(rows.at(row).at(column));
  }
  const std::string& text(size_t row, const std::string& column) const {
    return rows.at(row).at(column);
  }
};

inline Csv readCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << "missing " << path;
  Csv csv;
  std::string line;
  if (std::getline(in, line)) csv.columns = csvFields(line);
  while (std::getline(in, line)) {
    const std::vector<std::string> fields = csvFields(line);
    EXPECT_EQ(fields.size(), csv.columns.size()) << path << ": " << line;
    CsvRow row;
    for (size_t i = 0; i < fields.size() && i < csv.columns.size(); ++i)
      row[csv.columns[i]] = fields[i];
    csv.rows.push_back(row);
  }
  return csv;
}

}  // namespace ndtom::testing
