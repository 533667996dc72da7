// The red team of issue #17, reproducible: generates hostile inputs per category, runs
// ndtom-map and the loaders on each in a child process (time limit, address-space limit,
// peak memory measured), tells crashes, hangs, silently wrong results, lost data and runs
// over 1.5 GB apart from clean outcomes, and prints the table of doc/robustness.md.
//
//   ndtom-redteam --mapper PATH --probe PATH [--work DIR] [--only PREFIX] [--sample N]
//                 [--no-address-limit] [--no-memory-check] [--csv FILE]
//                 [--localizer PATH] [--worldgen PATH] [--rawlog-from-pcd PATH]
//                 [--mpi-mapper PATH] [--plugin LIBRARY] [--preload LIBRARY]
//
// Issue #38's categories (8-10) need ndtom-localize, ndtom-worldgen, ndtom-rawlog-from-pcd
// and the plugin (for MRPT's programs); the cases of a program not given are left out.
//
// Exit status 0 if every case is clean (an MRPT crash, confirmed by MRPT's own reader on the
// same file, does not count against it), 1 otherwise.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "cases.h"
#include "hostile_maps.h"

using namespace redteam;

namespace {

enum Column {
  kClean,
  kCrash,
  kHang,
  kSilentWrong,
  kDataLoss,
  kMemory,
  kUnclear,
  kMrptCrash,
  kColumns
};
const char* kColumnNames[kColumns] = {"clean",         "crash",        "hang",
                                      "silent wrong",  "data loss",    "memory >= 1.5 GB",
                                      "unclear error", "crash in MRPT"};

struct Options {
  std::string mapper, probe, work = "/tmp/ndtom-redteam", only, csv;
  std::string localizer, worldgen, rawlog_from_pcd, mpi_mapper, plugin, preload;
  int sample = 1;
  bool address_limit = true, memory_check = true;
};

Column classify(const Case& k, const Outcome& o, const std::string& note, const Options& opt) {
  if (o.timed_out) return kHang;
  if (note.rfind("mrpt:", 0) == 0) return kMrptCrash;
  if (o.signal != 0 && !o.signalled_by_us) return kCrash;
  const bool exited = o.exit_code >= 0;
  if (exited && o.exit_code != 0 && o.exit_code != 1 && o.exit_code != 2 && o.exit_code != 4 &&
      o.exit_code != 5)
    return kCrash;
  if (opt.memory_check && o.peak_rss >= uint64_t(1500) << 20) return kMemory;
  if (o.exit_code == 4 || note.rfind("data loss:", 0) == 0) return kDataLoss;
  if (o.exit_code == 5 || note.rfind("silent wrong:", 0) == 0) return kSilentWrong;
  if (o.exit_code == 0 && k.expect == Expect::Refuse) return kSilentWrong;
  if (o.exit_code == 1 || o.exit_code == 2) {
    if (k.expect == Expect::Accept) return kUnclear;  // a valid input refused
    if ((k.one_line && lineCount(o.err) != 1) || o.err.find("bad_alloc") != std::string::npos ||
        o.err.find("Cannot write bytes to stream") != std::string::npos)
      return kUnclear;
  }
  if (note.rfind("unclear:", 0) == 0) return kUnclear;
  return kClean;
}

std::string firstLine(const std::string& text) {
  const std::string line = text.substr(0, text.find('\n'));
  return line.size() > 160 ? line.substr(0, 157) + "..." : line;
}

std::string csvField(std::string s) {
  for (char& ch : s)
    if (ch == '"') ch = '\'';
  return "\"" + s + "\"";
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&] {
      if (i + 1 >= argc) throw std::runtime_error(a + ": missing value");
      return std::string(argv[++i]);
    };
    if (a == "--mapper")
      o.mapper = value();
    else if (a == "--probe")
      o.probe = value();
    else if (a == "--localizer")
      o.localizer = value();
    else if (a == "--worldgen")
      o.worldgen = value();
    else if (a == "--rawlog-from-pcd")
      o.rawlog_from_pcd = value();
    else if (a == "--mpi-mapper")
      o.mpi_mapper = value();
    else if (a == "--plugin")
      o.plugin = value();
    else if (a == "--preload")
      o.preload = value();
    else if (a == "--work")
      o.work = value();
    else if (a == "--only")
      o.only = value();
    else if (a == "--csv")
      o.csv = value();
    else if (a == "--sample")
      o.sample = std::max(1, std::stoi(value()));
    else if (a == "--no-address-limit")
      o.address_limit = false;
    else if (a == "--no-memory-check")
      o.memory_check = false;
    else
      throw std::runtime_error(a + ": unknown option");
  }
  if (o.mapper.empty() || o.probe.empty()) throw std::runtime_error("--mapper and --probe needed");
  return o;
}

}  // namespace

// The 1 GB bar is for the programs as users run them. Under AddressSanitizer the same run
// takes about twice the memory (shadow memory, redzones, the quarantine of freed blocks:
// 1000 points 60 km away took 542 MB in Release and 995-1095 MB under ASan), so the bar
// doubles there; the normal build's run of this test keeps it at 1 GB.
#if defined(__SANITIZE_ADDRESS__)
constexpr uint64_t kOneGigabyteHere = 2000000000;
#else
constexpr uint64_t kOneGigabyteHere = 1000000000;
#endif

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "--write")  // a child making a hostile map
    return writeHostileMap(std::vector<std::string>(argv + 2, argv + argc));
  Options opt;
  try {
    opt = parse(argc, argv);
    limitAddressSpace(opt.address_limit);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ndtom-redteam: %s\n", e.what());
    return 2;
  }
  // Absolute paths: some cases run in folders of their own.
  for (std::string* path : {&opt.mapper, &opt.probe, &opt.work, &opt.localizer, &opt.worldgen,
                            &opt.rawlog_from_pcd, &opt.mpi_mapper, &opt.plugin})
    if (!path->empty()) *path = std::filesystem::absolute(*path).string();
  std::filesystem::remove_all(opt.work);
  std::filesystem::create_directories(opt.work);
  Context c;
  c.mapper = opt.mapper;
  c.probe = opt.probe;
  c.work = opt.work;
  c.lidar = std::string(NDTOM_SOURCE_DIR) + "/tests/data/balm-realworld";
  c.tum = std::string(NDTOM_SOURCE_DIR) + "/share/data/tum-fr2-pioneer-slam2";
  c.localizer = opt.localizer;
  c.worldgen = opt.worldgen;
  c.rawlog_from_pcd = opt.rawlog_from_pcd;
  c.mpi_mapper = opt.mpi_mapper;
  c.plugin = opt.plugin;
  c.preload = opt.preload;
  c.self = std::filesystem::read_symlink("/proc/self/exe").string();
  std::vector<Case> cases;
  for (auto* make :
       {pcdHeaderCases, geometryMemoryCases, loaderCountCases, writableCases, silentValueCases,
        outputCases, smallCases, rawlogCases, localizeCases, optionCases, pluginCases}) {
    std::vector<Case> more = make(c);
    size_t sampleable = 0;  // every N-th of the category's cases that may be sampled
    for (size_t i = 0; i < more.size(); ++i)
      if (more[i].category.rfind(opt.only, 0) == 0 &&
          (opt.sample == 1 || (more[i].sampled && sampleable++ % size_t(opt.sample) == 0)))
        cases.push_back(std::move(more[i]));
  }
  std::map<std::string, std::array<int, kColumns + 1>> table;  // [kColumns]: tried
  std::map<std::string, uint64_t> max_rss_small;               // inputs under 10 MB
  int over_1gb_small = 0;
  std::ofstream csv;
  if (!opt.csv.empty()) {
    csv.open(opt.csv);
    csv << "category,case,verdict,exit,signal,seconds,peak_rss_mb,input_bytes,note,stderr\n";
  }
  std::vector<std::string> problems;
  int harness_errors = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    Case& k = cases[i];
    uint64_t input = 0;
    Outcome o;
    std::string note;
    try {
      input = k.setup ? k.setup() : 0;
      if (k.make_argv) k.argv = k.make_argv();
      o = runCommand(k.argv, k.limits, k.cwd);
      note = k.check ? k.check(o) : "";
    } catch (const std::exception& e) {  // the harness's own failure, not the program's
      ++harness_errors;
      problems.push_back("[" + std::to_string(i + 1) + "] harness error in " + k.category + " | " +
                         k.name + ": " + e.what());
      std::fprintf(stderr, "%s\n", problems.back().c_str());
      continue;
    }
    const Column verdict = classify(k, o, note, opt);
    auto& row = table[k.category];
    ++row[kColumns];
    ++row[verdict];
    if (input < 10000000 && verdict != kMrptCrash) {  // MRPT's reader's memory is not ours
      max_rss_small[k.category] = std::max(max_rss_small[k.category], o.peak_rss);
      over_1gb_small += o.peak_rss >= kOneGigabyteHere;
    }
    char line[512];
    std::snprintf(line, sizeof(line),
                  "[%zu/%zu] %-14s %s | %s: exit %d signal %d %.1f s %.0f MB %s", i + 1,
                  cases.size(), kColumnNames[verdict], k.category.c_str(), k.name.c_str(),
                  o.exit_code, o.signal, o.seconds, double(o.peak_rss) / 1e6,
                  firstLine(note.empty() ? o.err : note).c_str());
    std::fprintf(stderr, "%s\n", line);
    if (verdict != kClean) problems.push_back(line);
    if (csv)
      csv << csvField(k.category) << "," << csvField(k.name) << "," << kColumnNames[verdict] << ","
          << o.exit_code << "," << o.signal << "," << o.seconds << "," << double(o.peak_rss) / 1e6
          << "," << input << "," << csvField(note) << "," << csvField(firstLine(o.err)) << "\n";
  }
  std::printf("\n| category | tried |");
  for (const char* name : kColumnNames) std::printf(" %s |", name);
  std::printf(" max RSS, inputs < 10 MB, not MRPT's |\n|---|---:|");
  for (int col = 0; col < kColumns; ++col) std::printf("---:|");
  std::printf("---:|\n");
  std::array<int, kColumns + 1> total{};
  uint64_t max_all = 0;
  for (const auto& [category, row] : table) {
    std::printf("| %s | %d |", category.c_str(), row[kColumns]);
    for (int col = 0; col < kColumns; ++col) std::printf(" %d |", row[col]);
    std::printf(" %.0f MB |\n", double(max_rss_small[category]) / 1e6);
    for (int col = 0; col <= kColumns; ++col) total[col] += row[col];
    max_all = std::max(max_all, max_rss_small[category]);
  }
  std::printf("| **all** | %d |", total[kColumns]);
  for (int col = 0; col < kColumns; ++col) std::printf(" %d |", total[col]);
  std::printf(
      " %.0f MB |\n\nRuns of %.0f GB or more on inputs under 10 MB (but MRPT's crashes): %d\n",
      double(max_all) / 1e6, double(kOneGigabyteHere) / 1e9, over_1gb_small);
  if (!problems.empty()) {
    std::printf("\nNot clean:\n");
    for (const auto& p : problems) std::printf("  %s\n", p.c_str());
  }
  const int failures = harness_errors + total[kCrash] + total[kHang] + total[kSilentWrong] +
                       total[kDataLoss] + total[kMemory] + total[kUnclear] + over_1gb_small;
  return failures == 0 ? 0 : 1;
}
