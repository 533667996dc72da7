// The pose graph on MRPT's optimizer: a square drive with a known heading drift injected in
// its odometry edges and one loop edge, optimized; the file MRPT reads back.
#include <gtest/gtest.h>
#include <mrpt/graphs/CNetworkOfPoses.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <sstream>

#include "pose_graph.h"

using Eigen::Isometry3d;
using Eigen::Vector3d;
using ndtom::Matrix6d;
using ndtom::slam::PoseGraph;

namespace {

constexpr int kNodes = 20;  // a 50 m square, a node every 10 m

Isometry3d step(int i) {  // the true motion from node i to i + 1: 10 m, a left turn every 5
  return Eigen::Translation3d(10, 0, 0) *
         Eigen::AngleAxisd((i + 1) % 5 == 0 ? M_PI / 2 : 0, Vector3d::UnitZ());
}

Matrix6d covariance(double sigma_m, double sigma_rad) {
  Matrix6d c = Matrix6d::Zero();
  c.diagonal() << Vector3d::Constant(sigma_m * sigma_m), Vector3d::Constant(sigma_rad * sigma_rad);
  return c;
}

struct Square {
  std::vector<Isometry3d> truth, odometry;
  PoseGraph graph;
  Square() {
    // Odometry turns 1.5° too far at every edge: 28° off after the square.
    const Isometry3d bias(Eigen::AngleAxisd(1.5 * M_PI / 180, Vector3d::UnitZ()));
    truth.push_back(Isometry3d::Identity());
    odometry.push_back(Isometry3d::Identity());
    graph.addNode(odometry[0]);
    for (int i = 0; i + 1 < kNodes; ++i) {
      truth.push_back(truth.back() * step(i));
      const Isometry3d measured = step(i) * bias;
      odometry.push_back(odometry.back() * measured);
      graph.addNode(odometry.back());
      graph.addEdge(size_t(i), size_t(i + 1), measured, covariance(0.05, 0.03));
    }
    // The loop: the last node seen from the first, exactly.
    graph.addEdge(0, kNodes - 1, truth[0].inverse() * truth[kNodes - 1], covariance(0.02, 0.002));
  }
};

double worstError(const std::vector<Isometry3d>& truth,
                  const std::function<Isometry3d(size_t)>& pose) {
  double worst = 0;
  for (size_t i = 0; i < truth.size(); ++i)
    worst = std::max(worst, (pose(i).translation() - truth[i].translation()).norm());
  return worst;
}

}  // namespace

TEST(PoseGraph, MrptsOptimizerRemovesAnInjectedDrift) {
  Square s;
  const double before = worstError(s.truth, [&](size_t i) { return s.odometry[i]; });
  ASSERT_GT(before, 10.0);
  const auto result = s.graph.optimize();
  const double after = worstError(s.truth, [&](size_t i) { return s.graph.pose(i); });
  EXPECT_LT(after, 0.1 * before) << "before " << before << " m, after " << after << " m";
  EXPECT_LT(result.error_after, result.error_before);
  EXPECT_GT(result.iterations, 0u);
  EXPECT_TRUE(s.graph.pose(0).isApprox(Isometry3d::Identity(), 1e-12));  // the root stays
}

TEST(PoseGraph, MrptReadsTheGraphItWrites) {
  Square s;
  s.graph.optimize();
  mrpt::graphs::CNetworkOfPoses3DInf read;
  std::istringstream text(s.graph.text());
  read.readAsText(text);
  ASSERT_EQ(read.nodes.size(), size_t(kNodes));
  EXPECT_EQ(read.edgeCount(), size_t(kNodes));  // kNodes - 1 odometry edges and the loop
  for (size_t i = 0; i < size_t(kNodes); ++i) {
    const Vector3d p(read.nodes.at(i).x(), read.nodes.at(i).y(), read.nodes.at(i).z());
    EXPECT_LT((p - s.graph.pose(i).translation()).norm(), 1e-4) << i;
  }
}

TEST(PoseGraph, BadEdgesAreRefused) {
  PoseGraph g;
  g.addNode(Isometry3d::Identity());
  g.addNode(Isometry3d::Identity());
  EXPECT_THROW(g.addEdge(0, 2, Isometry3d::Identity(), Matrix6d::Identity()),
               std::invalid_argument);
  EXPECT_THROW(g.addEdge(0, 1, Isometry3d::Identity(), -Matrix6d::Identity()),
               std::invalid_argument);
}

// Two laps of a 400 m × 200 m block, a node every 10 m, odometry turning 0.05° too far at
// every edge, and loop edges from the second lap to the first: the optimized poses must be
// nearer the truth than odometry's everywhere.
TEST(PoseGraph, TwoLapsWithLoopEdgesBeatOdometry) {
  std::vector<Isometry3d> truth{Isometry3d::Identity()};
  const int per_lap = 120;  // 1200 m
  auto motion = [](int i) {
    const int k = i % 120;
    const bool corner = k == 39 || k == 59 || k == 99 || k == 119;
    return Isometry3d(Eigen::Translation3d(10, 0, 0) *
                      Eigen::AngleAxisd(corner ? M_PI / 2 : 0, Vector3d::UnitZ()));
  };
  const Isometry3d bias(Eigen::AngleAxisd(0.05 * M_PI / 180, Vector3d::UnitZ()));
  PoseGraph g;
  std::vector<Isometry3d> odometry{Isometry3d::Identity()};
  g.addNode(odometry[0]);
  for (int i = 0; i + 1 < 2 * per_lap; ++i) {
    truth.push_back(truth.back() * motion(i));
    odometry.push_back(odometry.back() * motion(i) * bias);
    g.addNode(odometry.back());
    g.addEdge(size_t(i), size_t(i + 1), motion(i) * bias, covariance(0.06, 0.3 * M_PI / 180));
  }
  for (int i = per_lap; i < 2 * per_lap; i += 3)
    g.addEdge(size_t(i - per_lap), size_t(i),
              truth[size_t(i - per_lap)].inverse() * truth[size_t(i)],
              covariance(0.05, 0.5 * M_PI / 180));
  const double before = worstError(truth, [&](size_t i) { return odometry[i]; });
  g.optimize();
  const double after = worstError(truth, [&](size_t i) { return g.pose(i); });
  EXPECT_LT(after, 0.2 * before) << "before " << before << " m, after " << after << " m";
}
