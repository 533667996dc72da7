// The kinds of input the programs read (ndtom-map, ndtom-localize, ...), and how the kind is
// told from the path.
#pragma once

#include <string>

#include "ndtom_apps/command_line.h"
#include "ndtom_io/pose_file.h"

namespace ndtom::apps {

enum class InputFormat {
  Auto,       ///< decide from the path (detectInputFormat)
  Rawlog,     ///< MRPT .rawlog, either format (actions + sensory frames, or observations)
  Simplemap,  ///< MRPT .simplemap / .simplemap.gz: keyframes with their poses
  TumRgbd,    ///< TUM RGB-D sequence folder: depth/ + associations or ground truth
  PcdFolder,  ///< folder of PCD scans + a pose file (KITTI poses.txt or TUM trajectory)
};

/// "rawlog", "simplemap", "tum", "pcd" (and "auto"); throws apps::UsageError otherwise.
InputFormat inputFormatFromName(const std::string& name);
const char* inputFormatName(InputFormat format);

/// "auto", "kitti" or "tum", given with `option`; throws apps::UsageError otherwise.
ndtom::io::PoseFormat poseFormatFromName(const std::string& option, const std::string& name);

/// `table` and the options that name a program's input and outputs: -o/--output PREFIX,
/// --format, --poses FILE, --pose-format (Options has prefix, format, poses_file and
/// pose_format).
template <typename Options>
OptionTable<Options> withInputOptions(OptionTable<Options> table) {
  const auto prefix = [](Options& o, const std::string& v) { o.prefix = v; };
  table["-o"] = {true, prefix};
  table["--output"] = {true, prefix};
  table["--format"] = {true,
                       [](Options& o, const std::string& v) { o.format = inputFormatFromName(v); }};
  table["--poses"] = {true, [](Options& o, const std::string& v) { o.poses_file = v; }};
  table["--pose-format"] = {true, [](Options& o, const std::string& v) {
                              o.pose_format = poseFormatFromName("--pose-format", v);
                            }};
  return table;
}

/// The format of `path`: by extension for files (.rawlog[.gz], .simplemap[.gz]), by content
/// for folders (associations.txt, depth.txt or groundtruth.txt: TUM; *.pcd files: PCD).
/// Throws apps::UsageError if the path does not exist or matches no format.
InputFormat detectInputFormat(const std::string& path);

/// Throws apps::UsageError "<what> <path>: <why>" unless `path`, given on the command line as
/// `what` (INPUT, --poses, --config), is a regular file: readers would wait forever on a FIFO
/// and read /dev/zero until memory ends. A bad command line, so exit status 2.
void requireRegularFile(const std::string& what, const std::string& path);

}  // namespace ndtom::apps
