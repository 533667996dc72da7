// ndtom-rawlog-from-pcd: a folder of posed lidar scans as a rawlog with noisy odometry, a
// ground-truth file and a simplemap, the inputs of MRPT's pf-localization (see
// doc/localization-pf.md). Exit code 0 on success, 1 for bad input data or a failed write,
// 2 for a bad command line.
#include <cstdio>

#include "ndtom_apps/run_program.h"
#include "pcd_to_rawlog.h"

int main(int argc, char** argv) {
  return ndtom::apps::runProgram("ndtom-rawlog-from-pcd", [&] {
    const auto options = ndtom::rawlog::parseRawlogOptions(argc, argv);
    if (options.help) {
      std::fputs(ndtom::rawlog::helpText().c_str(), stdout);
      return 0;
    }
    ndtom::apps::Progress progress(!options.quiet);
    const auto report = ndtom::rawlog::convertFolder(options, progress);
    if (!options.quiet) {
      std::printf("rawlog: %zu scans, %zu points; simplemap: %zu scans, %zu points\n",
                  report.log_scans, report.log_points, report.map_scans, report.map_points);
      for (const std::string& f : report.files) std::printf("wrote %s\n", f.c_str());
    }
    return 0;
  });
}
