// Issue #38, ndtom-localize with .ndtom, .ndtommap and .ndtomtiles maps: memory the
// registration pyramid and the recovery search take (class 1), tile drops over many tiles
// (class 2), a map whose values overflow (class 3), and poses reported placed that are far
// from the truth (class 4). The truth is the generated drive's poses.txt, read by the harness
// itself: any scan ndtom-localize calls tracked, recovered or relocalized more than 1 m from
// it is silently wrong.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "cases.h"
#include "hostile_files.h"

namespace fs = std::filesystem;

namespace redteam {

std::vector<Eigen::Vector3d> kittiPositions(const std::string& path) {
  std::ifstream in(path);
  std::vector<Eigen::Vector3d> positions;
  for (std::string line; std::getline(in, line);) {
    std::istringstream s(line);
    double v[12];
    int n = 0;
    while (n < 12 && s >> v[n]) ++n;
    if (n == 12) positions.emplace_back(v[3], v[7], v[11]);
  }
  return positions;
}

std::string initialPose(const std::string& poses, double dx, double dy, double yaw_deg,
                        size_t line_index) {
  std::ifstream in(poses);
  std::string line;
  for (size_t i = 0; i <= line_index; ++i) std::getline(in, line);
  std::istringstream s(line);
  double v[12] = {};
  for (double& x : v) s >> x;
  Eigen::Matrix3d r;
  r << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
  const Eigen::Quaterniond q(Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitZ()) * r);
  std::ostringstream out;
  out.precision(10);
  out << v[3] + dx << " " << v[7] + dy << " " << v[11] << " " << q.x() << " " << q.y() << " "
      << q.z() << " " << q.w();
  return out.str();
}

namespace {

// The fields of one CSV line (no quoting: ndtom-localize's cells have no commas).
std::vector<std::string> csvFields(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream s(line);
  for (std::string f; std::getline(s, f, ',');) fields.push_back(f);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

// The rows of PREFIX.scans.csv as column name -> value.
std::vector<std::map<std::string, std::string>> scanRows(const std::string& prefix) {
  std::ifstream in(prefix + ".scans.csv");
  std::string line;
  std::vector<std::map<std::string, std::string>> rows;
  if (!std::getline(in, line)) return rows;
  const std::vector<std::string> header = csvFields(line);
  while (std::getline(in, line)) {
    const std::vector<std::string> f = csvFields(line);
    auto& row = rows.emplace_back();
    for (size_t i = 0; i < header.size() && i < f.size(); ++i) row[header[i]] = f[i];
  }
  return rows;
}

double number(const std::map<std::string, std::string>& row, const std::string& key) {
  const auto it = row.find(key);
  return it == row.end() || it->second.empty() ? std::nan("")
                                               : std::strtod(it->second.c_str(), nullptr);
}

// poses.txt with every position moved by `dx` m in x.
void movedPoses(const std::string& in_path, const std::string& out_path, double dx) {
  std::ifstream in(in_path);
  std::ofstream out(out_path);
  out.precision(17);
  for (std::string line; std::getline(in, line);) {
    std::istringstream s(line);
    double v[12];
    for (double& x : v) s >> x;
    v[3] += dx;
    for (int i = 0; i < 12; ++i) out << v[i] << (i == 11 ? "\n" : " ");
  }
}

}  // namespace

std::string placedScansCheck(const std::string& prefix, const std::vector<Eigen::Vector3d>& truth,
                             double tolerance, bool none_placed) {
  const auto rows = scanRows(prefix);
  if (rows.empty()) return "silent wrong: exit 0 but no " + prefix + ".scans.csv rows";
  int wrong = 0, placed = 0;
  std::string first;
  for (const auto& row : rows) {
    const std::string outcome = row.count("outcome") ? row.at("outcome") : "";
    if (outcome == "lost") continue;
    ++placed;
    const double index = number(row, "index");
    const Eigen::Vector3d p(number(row, "x"), number(row, "y"), number(row, "z"));
    const bool known = index >= 0 && index < double(truth.size());
    const double off = known ? (p - truth[size_t(index)]).norm() : std::nan("");
    if (none_placed || !(off <= tolerance)) {
      if (wrong++ == 0) {
        std::ostringstream s;
        s.precision(3);
        s << "scan " << index << " " << outcome << " " << off << " m from the truth";
        first = s.str();
      }
    }
  }
  if (wrong == 0) return "";
  return "silent wrong: " + std::to_string(wrong) + " of " + std::to_string(rows.size()) +
         " scans placed" +
         (none_placed ? " (none can be)" : " > " + std::to_string(int(tolerance)) + " m off") +
         ", e.g. " + first;
}

std::vector<Case> localizeCases(const Context& c) {
  if (c.localizer.empty() || c.worldgen.empty()) return {};
  CaseSet set(c, "8 localization and tiled maps", "localize");
  const std::string dir = set.dir;
  // Prepared once, on first use: the city of seed 1 and its maps in all three formats.
  const auto city = [&c] { return c.city(1); };
  const auto map = [&c] { return c.cityMap(1, "seed1", {"--tiles", "2"}); };
  const auto truth = [&c] { return kittiPositions(c.city(1) + "/poses.txt"); };
  const auto initial = [&c](double dx, double dy, double yaw) {
    return initialPose(c.city(1) + "/poses.txt", dx, dy, yaw);
  };
  // A run of ndtom-localize on the city's scans: the command line is made after setup (the
  // city, its maps and the poses in it are made then); the oracle compares the scans placed
  // with the truth.
  struct Run {
    using Check = std::function<std::string(const Outcome&, const std::string& out)>;
    Run(std::string n, Expect e, std::function<std::string()> m,
        std::function<std::vector<std::string>()> a)
        : name(std::move(n)), expect(e), map_file(std::move(m)), args(std::move(a)) {}
    Run& limit(double seconds) { return timeout = seconds, *this; }
    Run& withPictures() { return pictures = true, *this; }
    Run& noOracle() { return oracle = false, *this; }
    Run& slow() { return sampled = false, *this; }
    Run& on(std::function<std::string()> in, std::function<std::vector<Eigen::Vector3d>()> t,
            bool nothing_placeable) {
      input = std::move(in), input_truth = std::move(t), none_placed = nothing_placeable;
      return *this;
    }
    Run& checked(Check c) { return check = std::move(c), *this; }

    std::string name;
    Expect expect;
    std::function<std::string()> map_file;                      // makes it
    std::function<std::vector<std::string>()> args;             // after map_file()
    std::function<std::string()> input;                         // default: the seed 1 city
    std::function<std::vector<Eigen::Vector3d>()> input_truth;  // default: its poses
    double timeout = 60;
    bool pictures = false;
    bool oracle = true;        // compare placed scans with the truth
    bool none_placed = false;  // no scan can be placed (another city)
    bool sampled = true;
    Check check;
  };
  const auto add = [&](const Run& r) {
    Case& k = set.add();
    k.name = r.name;
    k.expect = r.expect;
    k.sampled = r.sampled;
    k.limits.timeout_s = r.timeout;
    const std::string out = set.path("/loc");
    auto map_file = std::make_shared<std::string>();
    k.setup = [r, map_file, city] {
      if (!r.input) city();
      *map_file = r.map_file();
      return sizeOf(*map_file);
    };
    k.make_argv = [&c, r, out, map_file, city] {
      auto argv = c.localizer_args(*map_file, r.input ? r.input() : city(), out, r.args());
      if (r.pictures) argv.erase(std::find(argv.begin(), argv.end(), "--no-pictures"));
      return argv;
    };
    k.check = [r, out, truth](const Outcome& o) -> std::string {
      if (r.check) {
        const std::string note = r.check(o, out);
        if (!note.empty()) return note;
      }
      if (o.exit_code != 0 || !r.oracle) return "";
      return placedScansCheck(out, r.input_truth ? r.input_truth() : truth(), 1.0, r.none_placed);
    };
  };
  const auto ndtom = [map] { return map() + ".ndtom"; };
  const auto ndtommap = [map] { return map() + ".ndtommap"; };
  const auto tiles = [map] { return map() + ".ndtomtiles"; };
  const auto atTruth = [initial](std::vector<std::string> more) {
    return [initial, more] {
      std::vector<std::string> a = {"--initial", initial(0, 0, 0)};
      a.insert(a.end(), more.begin(), more.end());
      return a;
    };
  };
  const auto plain = [](std::vector<std::string> a) { return [a] { return a; }; };

  // The baselines: the city's own scans in its own map, from the true first pose.
  add(Run("baseline .ndtom", Expect::Accept, ndtom, atTruth({})));
  add(Run("baseline .ndtommap", Expect::Accept, ndtommap, atTruth({})));
  add(Run("baseline .ndtomtiles, --region-radius 30", Expect::Accept, tiles,
          atTruth({"--region-radius", "30"})));

  // Class 1: memory that is not budgeted. A map of one Gaussian per block: a few MB of file,
  // tens of thousands of blocks, each level of the registration pyramid over them.
  const auto sparse = [&c, dir](const std::string& format, int blocks, int tile_blocks) {
    return [&c, dir, format, blocks, tile_blocks] {
      const std::string path = dir + "/sparse-" + std::to_string(blocks) + "-" +
                               std::to_string(tile_blocks) + "." +
                               (format == "tiles" ? "ndtomtiles" : format);
      if (c.made->insert(path).second) {
        std::vector<std::string> a = {"sparse", format, "grid", std::to_string(blocks), path};
        if (format == "tiles") a.push_back(std::to_string(tile_blocks));
        c.writeHostile(a);
      }
      return path;
    };
  };
  const auto origin = plain({"--initial", "0 0 0 0 0 0 1", "--max-scans", "3"});
  for (const int blocks : {20000, 85000}) {
    const std::string b = std::to_string(blocks / 1000) + "k blocks";
    Run ndtom_file("one Gaussian per block, " + b + ", .ndtom", Expect::Either,
                   sparse("ndtom", blocks, 0), origin);
    if (blocks > 50000) ndtom_file.slow();
    add(ndtom_file.limit(120).noOracle());
    add(Run("one Gaussian per block, " + b + ", .ndtommap (gzip)", Expect::Either,
            sparse("ndtommap", blocks, 0), origin)
            .limit(120)
            .noOracle()
            .slow());
    add(Run("one Gaussian per block, " + b + ", .ndtomtiles of 4096 blocks (a few tiles)",
            Expect::Either, sparse("tiles", blocks, 4096), origin)
            .limit(120)
            .noOracle()
            .slow());
  }
  // More blocks than the default budget (512 MB) holds, in 8 tiles: a refusal names the file.
  add(Run("one Gaussian per block, 230k blocks, tiles of 4096 blocks (over the budget)",
          Expect::Either, sparse("tiles", 230000, 4096), origin)
          .limit(120)
          .noOracle()
          .slow()
          .checked([](const Outcome& o, const std::string&) -> std::string {
            if (o.exit_code == 1 && o.err.find(".ndtomtiles") == std::string::npos)
              return "unclear: the refusal names no file";
            return "";
          }));
  // The recovery search: hypotheses over a 200 m square in 0.1 m steps (both in range).
  for (const char* step : {"0.1", "0.5"})
    add(Run(std::string("--recovery-radius 100 --search-step ") + step + ", start 30 m off",
            Expect::Either, ndtom,
            [initial, step] {
              return std::vector<std::string>{"--initial",         initial(30, 0, 0),
                                              "--recovery-radius", "100",
                                              "--search-step",     step,
                                              "--max-scans",       "2"};
            })
            .limit(120)
            .slow());

  // Class 2: dropping tiles walks every resident block per tile. The city in tiles of one
  // block (thousands of tiles), the first scan searched for in the whole map (every tile
  // loaded), the next ones tracked with a small region: most tiles dropped at once.
  const auto tiles1 = [&c] {
    return c.cityMap(1, "seed1-tiles1", {"--tiles", "1"}) + ".ndtomtiles";
  };
  add(Run("tiles of 1 block, whole-map search then --region-radius 10", Expect::Either, tiles1,
          plain({"--region-radius", "10", "--max-scans", "3"}))
          .slow());
  add(Run("tiles of 1 block, --relocalize 1 --region-radius 10", Expect::Either, tiles1,
          atTruth({"--region-radius", "10", "--relocalize", "1", "--max-scans", "4"}))
          .slow());

  // Class 3: a map whose scatter is diag(1e308) (or 1e200): refused at load, naming the file.
  const auto scattered = [&c, dir, ndtom](const std::string& value) {
    return [&c, dir, ndtom, value] {
      const std::string path = dir + "/scatter-" + value + ".ndtom";
      if (c.made->insert(path).second) c.writeHostile({"scatter", ndtom(), path, value});
      return path;
    };
  };
  const auto namesMap = [](const Outcome& o, const std::string&) -> std::string {
    if (o.exit_code == 1 && o.err.find(".ndtom") == std::string::npos)
      return "unclear: the refusal names no map file";
    return "";
  };
  add(Run("scatter diag(1e308)", Expect::Refuse, scattered("1e308"), atTruth({}))
          .checked(namesMap));
  add(Run("scatter diag(1e308), pictures", Expect::Refuse, scattered("1e308"), atTruth({}))
          .withPictures()
          .slow()
          .checked(namesMap));
  add(Run("scatter diag(1e200)", Expect::Refuse, scattered("1e200"), atTruth({}))
          .slow()
          .checked(namesMap));
  add(Run("scatter diag(1e154), pictures", Expect::Either, scattered("1e154"), atTruth({}))
          .withPictures()
          .slow()
          .checked(namesMap));

  // Class 4: silently wrong answers.
  // --reference moved 100 m: the errors reported must be about 100 m.
  add(Run("--reference moved 100 m", Expect::Accept, ndtom, [dir, city, initial] {
        movedPoses(city() + "/poses.txt", dir + "/moved.txt", 100);
        return std::vector<std::string>{"--initial", initial(0, 0, 0), "--reference",
                                        dir + "/moved.txt"};
      }).checked([](const Outcome& o, const std::string& out) -> std::string {
    if (o.exit_code != 0) return "";
    for (const auto& row : scanRows(out)) {
      const double e = number(row, "error_m");
      if (row.at("outcome") != "lost" && !(e > 90 && e < 110))
        return "silent wrong: scan " + row.at("index") + " reported error " + row.at("error_m") +
               " m against a reference 100 m away";
    }
    return "";
  }));
  // Registration options that make wrong poses likely: the verdict must call them lost.
  for (const char* levels : {"1", "2,1", "64,1", "1024,16,4,1"})
    add(Run(std::string("--levels ") + levels, Expect::Either, ndtom,
            atTruth({"--levels", levels})));
  add(Run("--levels 1, start 3 m off", Expect::Either, ndtom, [initial] {
        return std::vector<std::string>{"--initial", initial(3, 0, 0), "--levels", "1"};
      }).slow());
  add(Run("start 3 m and 20 degrees off", Expect::Either, ndtom, [initial] {
        return std::vector<std::string>{"--initial", initial(3, 1, 20)};
      }).slow());
  add(Run("start 6 m off (outside --recovery-radius 4)", Expect::Either, ndtom, [initial] {
        return std::vector<std::string>{"--initial", initial(6, 0, 0)};
      }).slow());
  add(Run("no --initial (global search), --relocalize 2", Expect::Either, ndtom,
          plain({"--relocalize", "2"}))
          .limit(90)
          .slow());
  add(Run("--min-matched-fraction 1", Expect::Either, ndtom,
          atTruth({"--min-matched-fraction", "1"}))
          .slow());
  add(Run("--min-matched-fraction 0 --levels 1", Expect::Either, ndtom,
          atTruth({"--min-matched-fraction", "0", "--levels", "1"}))
          .slow());
  add(Run("--skip 5 from scan 5's pose", Expect::Either, ndtom, [city] {
        return std::vector<std::string>{"--initial", initialPose(city() + "/poses.txt", 0, 0, 0, 5),
                                        "--skip", "5"};
      }).slow());
  // Scans of another city (--seed 2) in the seed 1 map: no scan can be placed.
  const auto city2 = [&c] { return c.city(2); };
  const auto truth2 = [&c] { return kittiPositions(c.city(2) + "/poses.txt"); };
  add(Run("scans of city seed 2 in the seed 1 map, from seed 2's start", Expect::Either, ndtom,
          [city2] {
            return std::vector<std::string>{"--initial", initialPose(city2() + "/poses.txt")};
          })
          .on(city2, truth2, true)
          .slow());
  add(Run("scans of city seed 2 in the seed 1 map, global search", Expect::Either, ndtom,
          plain({"--relocalize", "3"}))
          .on(city2, truth2, true)
          .limit(90)
          .slow());
  // A map with occupancy disabled (Recursive NDT): no free space to judge poses by.
  add(Run(
          "map with occupancy disabled", Expect::Either,
          [&c] {
            return c.cityMap(1, "seed1-noocc", {"--occupancy-enabled", "false"}) + ".ndtom";
          },
          atTruth({}))
          .slow());

  // Class 6: a failed --save-map names its file.
  add(Run("--save-map under a regular file", Expect::Refuse, ndtom,
          [dir, initial] {
            std::ofstream(dir + "/plain-file") << "x";
            return std::vector<std::string>{"--initial", initial(0, 0, 0), "--max-scans",
                                            "2",         "--save-map",     dir + "/plain-file/ext"};
          })
          .noOracle()
          .checked([dir](const Outcome& o, const std::string&) -> std::string {
            if (o.exit_code == 1 && o.err.find(dir + "/plain-file") == std::string::npos)
              return "unclear: the message names no file";
            return "";
          }));
  return set.cases;
}

}  // namespace redteam
