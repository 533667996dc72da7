// Issue #38, the plugin's .ini inside MRPT's own programs (observations2map builds a map from
// MRPT's demo simplemap, pf-localization localizes in it): values MRPT's lenient readers take
// for something else (class 4), a likelihood scale that overflows MRPT's weights (class 3);
// ndtom-map --config with the same values as a control. And the user's files named like
// leftovers beside ndtom-localize's and ndtom-map's outputs (class 5).
#include <filesystem>
#include <fstream>

#include "cases.h"
#include "hostile_files.h"
#include "ndtom/files/map_io.h"

namespace fs = std::filesystem;

namespace redteam {
namespace {

const std::string kDatasets = "/usr/share/mrpt/datasets";

// An .ini of sections, each key = value (the order of keys kept as given).
using Ini = std::vector<std::pair<std::string, std::vector<std::pair<std::string, std::string>>>>;

std::string iniText(const Ini& ini) {
  std::string text;
  for (const auto& [section, keys] : ini) {
    text += "[" + section + "]\n";
    for (const auto& [key, value] : keys) text += key + " = " + value + "\n";
  }
  return text;
}

// `keys` with `key` set to `value` (replaced where it is, else appended).
void setKey(std::vector<std::pair<std::string, std::string>>& keys, const std::string& key,
            const std::string& value) {
  for (auto& kv : keys)
    if (kv.first == key) {
      kv.second = value;
      return;
    }
  keys.emplace_back(key, value);
}

// The map section prefix of observations2map's and pf-localization's .ini files.
const std::string kInsert = "_ndtOccupancyMap_00_insertOpts";
const std::string kLikelihood = "_ndtOccupancyMap_00_likelihoodOpts";

}  // namespace

std::vector<Case> pluginCases(const Context& c) {
  if (c.plugin.empty() || c.localizer.empty()) return {};
  CaseSet set(c, "10 plugin .ini and outputs", "plugin");
  const std::string dir = set.dir;
  // MRPT's programs with the plugin preloaded; their exit status 255 (an exception caught in
  // main) as 1, a signal as 128 + signal (a crash either way).
  const std::string wrapper = dir + "/with-plugin.sh";
  // MRPT's own leaks are not ours to report.
  const std::string preload = c.preload.empty() ? "" : c.preload + ":";
  std::ofstream(wrapper) << "#!/bin/sh\nplugin=$1\nshift\nASAN_OPTIONS=detect_leaks=0 LD_PRELOAD=\""
                         << preload
                         << "$plugin\" \"$@\" </dev/null\n"
                            "rc=$?\n[ $rc -eq 255 ] && exit 1\nexit $rc\n";
  fs::permissions(wrapper, fs::perms::owner_all);
  const bool mrpt_programs = fs::exists("/usr/bin/observations2map") &&
                             fs::exists(kDatasets + "/localization_demo.rawlog");

  // observations2map CONFIG.ini demo.simplemap OUT with one insertOpts or likelihoodOpts key
  // set; `expected` checks the map it wrote when it accepts the value ("" if fine).
  const auto o2m = [&](const std::string& name, const std::string& section, const std::string& key,
                       const std::string& value, Expect expect,
                       std::function<std::string(const ndtom::NdtMap&)> expected = {}) {
    Case& k = set.add();
    k.name = "observations2map, " +
             (section == kInsert ? std::string("insertOpts ") : std::string("likelihoodOpts ")) +
             key + " = " + value + (name.empty() ? "" : " (" + name + ")");
    k.expect = expect;
    k.one_line = false;
    k.limits.timeout_s = 60;
    const std::string run = set.path("");
    const std::string ini = run + "/map.ini";
    k.cwd = run;
    k.argv = {wrapper,
              c.plugin,
              "/usr/bin/observations2map",
              ini,
              kDatasets + "/localization_demo.simplemap.gz",
              "out"};
    Ini text = {{"MappingApplication", {{"ndtOccupancyMap_count", "1"}}},
                {"MappingApplication" + kInsert, {{"resolution", "0.2"}, {"max_range", "30"}}},
                {"MappingApplication" + kLikelihood, {{"decimation", "5"}}}};
    setKey(text[section == kInsert ? 1 : 2].second, key, value);
    k.setup = [run, ini, text] {
      fs::create_directories(run);
      std::ofstream(ini) << iniText(text);
      return uint64_t(fs::file_size(kDatasets + "/localization_demo.simplemap.gz"));
    };
    k.check = [run, key, value, expected](const Outcome& o) -> std::string {
      if (o.exit_code == 1 && o.err.find(key) == std::string::npos)
        return "unclear: the refusal does not name " + key;
      if (o.exit_code == 1 && value.empty() && o.err.find(key + " = 0") != std::string::npos)
        return "unclear: an empty value reported as 0";
      if (o.exit_code != 0 || !expected) return "";
      const std::string file = run + "/out_mrpt_ndtom__CNDTOccupancyMap_00.ndtom";
      try {
        return expected(ndtom::loadMap(file));
      } catch (const std::exception& e) {
        return std::string("silent wrong: the map written cannot be read: ") + e.what();
      }
    };
  };
  const auto occupancy = [](bool on) {
    return [on](const ndtom::NdtMap& m) -> std::string {
      return m.options().occupancy.enabled == on
                 ? ""
                 : std::string("silent wrong: occupancy_enabled read as ") +
                       (on ? "false" : "true");
    };
  };
  const auto resolution = [](double r) {
    return [r](const ndtom::NdtMap& m) -> std::string {
      return m.options().resolution == r
                 ? ""
                 : "silent wrong: resolution read as " + std::to_string(m.options().resolution);
    };
  };
  if (mrpt_programs) {
    o2m("the shipped values", kInsert, "resolution", "0.2", Expect::Accept, resolution(0.2));
    o2m("", kInsert, "occupancy_enabled", "true", Expect::Accept, occupancy(true));
    o2m("", kInsert, "occupancy_enabled", "false", Expect::Accept, occupancy(false));
    o2m("", kInsert, "occupancy_enabled", "maybe", Expect::Refuse);
    o2m("", kInsert, "occupancy_enabled", "on", Expect::Either, occupancy(true));
    o2m("", kInsert, "occupancy_enabled", "yes", Expect::Either, occupancy(true));
    o2m("", kInsert, "occupancy_enabled", "2", Expect::Refuse);
    o2m("", kInsert, "occupancy_enabled", "-1", Expect::Refuse);
    o2m("", kInsert, "decimation", "4294967298", Expect::Refuse);
    o2m("", kInsert, "decimation", "2.5", Expect::Refuse);
    o2m("", kInsert, "decimation", "1e3", Expect::Refuse);
    o2m("", kInsert, "decimation_3d_range", "4294967297", Expect::Refuse);
    o2m("", kInsert, "resolution", "0.2abc", Expect::Refuse);
    o2m("", kInsert, "resolution", "0.2.5", Expect::Refuse);
    o2m("empty", kInsert, "resolution", "", Expect::Refuse);
    o2m("", kInsert, "max_range", "100m", Expect::Refuse);
    o2m("", kInsert, "p_hit", "0.7x", Expect::Refuse);
    o2m("strict already", kInsert, "threads", "4294967298", Expect::Refuse);
    o2m("strict already", kInsert, "ray_mode", "PerPointX", Expect::Refuse);
    o2m("", kLikelihood, "decimation", "4294967298", Expect::Refuse);
    o2m("", kLikelihood, "search_neighbours", "maybe", Expect::Refuse);
    o2m("", kLikelihood, "scale", "0.1x", Expect::Refuse);
    o2m("", kLikelihood, "scale", "1e400", Expect::Refuse);
  }

  // ndtom-map --config with the same values: its reader is strict (a control).
  for (const auto& [key, value] :
       std::vector<std::pair<std::string, std::string>>{{"occupancy_enabled", "maybe"},
                                                        {"occupancy_enabled", "2"},
                                                        {"decimation", "4294967298"},
                                                        {"resolution", "0.2abc"},
                                                        {"max_range", "100m"},
                                                        {"resolution", ""}}) {
    Case& k = set.add();
    k.name = "ndtom-map --config, " + key + " = " + value;
    const std::string ini = set.path(".ini");
    k.argv = c.mapper_args(c.tum, set.path("/map"), {"--config", ini, "--max-scans", "1"});
    k.limits.timeout_s = 30;
    k.setup = [ini, key = key, value = value] {
      std::ofstream(ini) << "[MetricMap_ndtOccupancyMap_00_insertOpts]\n"
                         << key << " = " << value << "\n";
      return uint64_t(1400000);
    };
    k.check = [key = key](const Outcome& o) -> std::string {
      if (o.exit_code != 0 && o.err.find(key) == std::string::npos)
        return "unclear: the refusal does not name " + key;
      return "";
    };
  }

  // pf-localization (3D particles, MRPT's demo log) with a likelihood scale that overflows
  // the particles' weights: bounded (clamped or refused), never MRPT's assertion.
  if (mrpt_programs && fs::exists("/usr/bin/pf-localization"))
    for (const char* scale : {"1e308", "1e200", "1e30"}) {
      Case& k = set.add();
      k.name = std::string("pf-localization, likelihoodOpts scale = ") + scale;
      k.expect = Expect::Either;
      k.one_line = false;
      k.sampled = false;
      k.limits.timeout_s = 120;
      const std::string run = set.path("");
      const std::string ini = run + "/pf.ini";
      k.cwd = run;
      k.argv = {wrapper, c.plugin, "/usr/bin/pf-localization", ini};
      const Ini text = {{"LocalizationExperiment",
                         {{"use_3D_poses", "true"},
                          {"map_file", kDatasets + "/localization_demo.simplemap.gz"},
                          {"rawlog_file", kDatasets + "/localization_demo.rawlog"},
                          {"logOutput_dir", "LOG_PF"},
                          {"particles_count", "200"},
                          {"init_PDF_mode", "1"},
                          {"init_PDF_min_x", "2"},
                          {"init_PDF_max_x", "5"},
                          {"init_PDF_min_y", "-11.5"},
                          {"init_PDF_max_y", "-9.5"},
                          {"init_PDF_min_yaw_deg", "-50"},
                          {"init_PDF_max_yaw_deg", "10"},
                          {"3DSceneFrequency", "-1"},
                          {"SHOW_PROGRESS_3D_REAL_TIME", "false"},
                          {"experimentRepetitions", "1"}}},
                        {"PF_options",
                         {{"PF_algorithm", "0"},
                          {"resamplingMethod", "0"},
                          {"adaptiveSampleSize", "0"},
                          {"BETA", "0.5"},
                          {"sampleSize", "1"}}},
                        {"KLD_options",
                         {{"KLD_binSize_PHI_deg", "10"},
                          {"KLD_binSize_XY", "0.10"},
                          {"KLD_delta", "0.01"},
                          {"KLD_epsilon", "0.01"},
                          {"KLD_maxSampleSize", "300"},
                          {"KLD_minSampleSize", "150"},
                          {"KLD_minSamplesPerBin", "0"}}},
                        {"DummyOdometryParams", {{"minStdXY", "0.10"}, {"minStdPHI", "2.0"}}},
                        {"MetricMap", {{"ndtOccupancyMap_count", "1"}}},
                        {"MetricMap" + kInsert, {{"resolution", "0.2"}, {"max_range", "30"}}},
                        {"MetricMap" + kLikelihood,
                         {{"decimation", "5"}, {"outlier_likelihood", "0.05"}, {"scale", scale}}}};
      k.setup = [run, ini, text] {
        fs::create_directories(run);
        std::ofstream(ini) << iniText(text);
        return uint64_t(fs::file_size(kDatasets + "/localization_demo.rawlog"));
      };
      k.check = [](const Outcome& o) -> std::string {
        if (o.exit_code == 1 && o.err.find("scale") == std::string::npos)
          return "unclear: the refusal does not name scale";
        return "";
      };
    }

  // Class 5: the user's files named like leftovers of a dead run survive a successful run.
  const std::vector<std::string> lookalikes = {".old-20241203", ".tmp-777777", ".old-31337"};
  const auto lookalikeCase = [&](const std::string& name, const std::string& prefix,
                                 std::vector<std::string> suffixes,
                                 std::function<std::vector<std::string>()> argv) {
    Case& k = set.add();
    k.name = name;
    k.expect = Expect::Accept;
    k.limits.timeout_s = 60;
    std::vector<std::string> files;
    for (const std::string& s : suffixes)
      for (const std::string& l : lookalikes) files.push_back(prefix + s + l);
    files.push_back(prefix + ".mydata.old-31337");
    k.setup = [files] {
      for (const std::string& f : files) {
        fs::create_directories(fs::path(f).parent_path());
        std::ofstream(f) << "mine";
      }
      return uint64_t(0);
    };
    k.make_argv = argv;
    k.check = [files](const Outcome&) -> std::string {
      for (const std::string& f : files)
        if (!fs::exists(f) || readFile(f) != "mine")
          return "data loss: the user's " + f + (fs::exists(f) ? " changed" : " is gone");
      return "";
    };
  };
  {
    const std::string out = dir + "/lookalike-localize/run";
    lookalikeCase("ndtom-localize beside the user's run.tum.old-20241203 and the like", out,
                  {".tum", ".scans.csv", ".summary.json", ".top.png"}, [&c, out] {
                    return std::vector<std::string>{
                        c.localizer, c.cityMap(1, "seed1", {"--tiles", "2"}) + ".ndtom", c.city(1),
                        "-o", out, "-q", "--max-scans", "3", "--initial",
                        // The scans start at the map's first pose.
                        initialPose(c.city(1) + "/poses.txt")};
                  });
  }
  {
    const std::string out = dir + "/lookalike-save-map/run";
    const std::string ext = dir + "/lookalike-save-map/extended";
    lookalikeCase("ndtom-localize --save-map beside the user's extended.ndtom.old-20241203", ext,
                  {".ndtom"}, [&c, out, ext] {
                    return std::vector<std::string>{
                        c.localizer,
                        c.cityMap(1, "seed1", {"--tiles", "2"}) + ".ndtom",
                        c.city(1),
                        "-o",
                        out,
                        "-q",
                        "--no-pictures",
                        "--max-scans",
                        "2",
                        "--save-map",
                        ext};
                  });
  }
  {
    const std::string out = dir + "/lookalike-tiles/run";
    lookalikeCase("ndtom-map --tiles 2 beside the user's run.ndtomtiles.old-20241203", out,
                  {".ndtomtiles", ".ndtom", ".ndtommap"}, [&c, out] {
                    return c.mapper_args(c.tum, out, {"--max-scans", "2", "--tiles", "2"});
                  });
  }
  return set.cases;
}

}  // namespace redteam
