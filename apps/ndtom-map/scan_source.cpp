#include "scan_source.h"

#include "ndtom_apps/option_values.h"

namespace ndtom::mapper {

std::unique_ptr<ScanSource> openScanSource(const SourceSettings& settings) {
  SourceSettings s = settings;
  if (s.format == InputFormat::Auto) s.format = detectInputFormat(s.input);
  switch (s.format) {
    case InputFormat::PcdFolder:
      return openPcdFolder(s);
    case InputFormat::TumRgbd:
      return openTumSequence(s);
    case InputFormat::Rawlog:
      return openRawlog(s);
    case InputFormat::Simplemap:
      return openSimplemap(s);
    case InputFormat::Auto:
      break;
  }
  throw apps::UsageError(s.input + ": unknown input format");
}

}  // namespace ndtom::mapper
