// The line plots of the evaluation (ndtom_apps/line_plot.h), with one colour per method used
// in every figure.
#pragma once

#include "ndtom_apps/line_plot.h"

namespace ndtom::eval {

using apps::PlotAxes;
using apps::PlotSeries;
using apps::writeLinePlot;

/// Colours used for the same method in every figure.
namespace colors {
inline const cv::Scalar kRecursive{200, 90, 30};  // blue
inline const cv::Scalar kNdtOm{40, 150, 40};      // green
inline const cv::Scalar kEr{40, 40, 210};         // red
inline const cv::Scalar kBatch{60, 60, 60};       // grey
inline const cv::Scalar kOther{0, 140, 230};      // orange
}  // namespace colors

}  // namespace ndtom::eval
