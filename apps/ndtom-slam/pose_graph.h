// The keyframes' pose graph on MRPT's engine: a CNetworkOfPoses3DInf with odometry and loop
// edges, optimized by mrpt::graphslam::optimize_graph_spa_levmarq, written in MRPT's text
// format (graph-slam and MRPT's viewers read it). Node i is keyframe i; node 0 stays fixed.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "ndtom/registration/registration.h"

namespace ndtom::slam {

struct GraphOptimization {
  size_t iterations = 0;
  double error_before = 0, error_after = 0;  ///< sum of squared edge errors, information-weighted
  double seconds = 0;
};

class PoseGraph {
 public:
  PoseGraph();
  ~PoseGraph();
  /// A node at `pose`; returns its id (0, 1, ...).
  size_t addNode(const Eigen::Isometry3d& pose);
  /// An edge from → to measuring from⁻¹·to, its error's covariance over [translation,
  /// rotation vector] in its own frame (MRPT's SE(3) tangent). Throws std::invalid_argument
  /// for a missing node or a covariance that is not positive definite.
  void addEdge(size_t from, size_t to, const Eigen::Isometry3d& relative,
               const Matrix6d& covariance);
  GraphOptimization optimize();
  size_t nodes() const;
  size_t edges() const;
  Eigen::Isometry3d pose(size_t node) const;
  /// MRPT's text format (CNetworkOfPoses::writeAsText).
  std::string text() const;

 private:
  struct Graph;
  std::unique_ptr<Graph> graph_;
};

}  // namespace ndtom::slam
