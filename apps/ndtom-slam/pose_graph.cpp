#include "pose_graph.h"

#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/graphslam/levmarq.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/poses/CPose3D.h>

#include <chrono>
#include <sstream>
#include <stdexcept>

#include "ndtom_apps/process_clock.h"

namespace ndtom::slam {
namespace {

mrpt::poses::CPose3D toMrpt(const Eigen::Isometry3d& pose) {
  mrpt::math::CMatrixDouble44 m;
  m.asEigen() = pose.matrix();
  return mrpt::poses::CPose3D::FromHomogeneousMatrix(m);
}

Eigen::Isometry3d fromMrpt(const mrpt::poses::CPose3D& pose) {
  Eigen::Isometry3d t;
  t.matrix() = pose.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen();
  return t;
}

}  // namespace

struct PoseGraph::Graph {
  mrpt::graphs::CNetworkOfPoses3DInf network;
};

PoseGraph::PoseGraph() : graph_(std::make_unique<Graph>()) {
  graph_->network.root = 0;
}
PoseGraph::~PoseGraph() = default;

size_t PoseGraph::addNode(const Eigen::Isometry3d& pose) {
  const size_t id = graph_->network.nodes.size();
  graph_->network.nodes[id] = toMrpt(pose);
  return id;
}

void PoseGraph::addEdge(size_t from, size_t to, const Eigen::Isometry3d& relative,
                        const Matrix6d& covariance) {
  if (from >= nodes() || to >= nodes())
    throw std::invalid_argument("PoseGraph::addEdge: no such node");
  const Eigen::LLT<Matrix6d> llt(covariance);
  if (llt.info() != Eigen::Success || !covariance.allFinite())
    throw std::invalid_argument("PoseGraph::addEdge: covariance not positive definite");
  mrpt::poses::CPose3DPDFGaussianInf edge;
  edge.mean = toMrpt(relative);
  // The SPA optimizer weighs the SE(3) log error [translation, rotation vector] by cov_inv.
  edge.cov_inv.asEigen() = llt.solve(Matrix6d::Identity());
  graph_->network.insertEdge(from, to, edge);
}

GraphOptimization PoseGraph::optimize() {
  const auto start = std::chrono::steady_clock::now();
  GraphOptimization out;
  out.error_before = graph_->network.chi2();
  mrpt::graphslam::TResultInfoSpaLevMarq info;
  mrpt::containers::yaml params = mrpt::containers::yaml::Map();
  params["max_iterations"] = 200;
  mrpt::graphslam::optimize_graph_spa_levmarq(graph_->network, info, nullptr, params);
  out.iterations = info.num_iters;
  out.error_after = graph_->network.chi2();
  out.seconds = apps::secondsSince(start);
  return out;
}

size_t PoseGraph::nodes() const {
  return graph_->network.nodes.size();
}
size_t PoseGraph::edges() const {
  return graph_->network.edgeCount();
}

Eigen::Isometry3d PoseGraph::pose(size_t node) const {
  return fromMrpt(graph_->network.nodes.at(node));
}

std::string PoseGraph::text() const {
  std::ostringstream s;
  graph_->network.writeAsText(s);
  return s.str();
}

}  // namespace ndtom::slam
