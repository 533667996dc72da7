// The 1-σ ellipse of a Gaussian's horizontal (xy) marginal: what the top views draw for
// each Gaussian, in metres and in the angle convention of images (y pointing down).
#pragma once

#include <Eigen/Core>

namespace ndtom::apps {

struct XyEllipse {
  double sigma_major = 0, sigma_minor = 0;  ///< semi-axes (m), the marginal's 1-σ lengths
  /// Direction of the major axis (degrees) measured from +x towards -y: the angle an image
  /// whose rows grow downwards (cv::ellipse) takes for the same ellipse.
  double image_angle = 0;
};

/// From the 3x3 covariance (m²); negative eigenvalues from rounding count as 0.
XyEllipse xyEllipse(const Eigen::Matrix3d& covariance);

}  // namespace ndtom::apps
