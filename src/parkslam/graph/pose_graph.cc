#include "parkslam/graph/pose_graph.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>
#include <string>

#include "parkslam/graph/pose_edge_factor.h"

namespace parkslam::graph {
namespace {

template <int N>
bool IsSymmetricPositiveDefinite(const Eigen::Matrix<double, N, N>& m) {
  if (!m.allFinite()) return false;
  const double scale = m.cwiseAbs().maxCoeff();
  if (!((m - m.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale)) return false;
  return Eigen::LLT<Eigen::Matrix<double, N, N>>(m).info() == Eigen::Success;
}

std::string EdgeName(const char* kind, size_t index, int a, int b) {
  return std::string(kind) + " " + std::to_string(index) + " (" + std::to_string(a) + " -> " +
         std::to_string(b) + ")";
}

}  // namespace

Eigen::Vector3d PoseEdgeError(const PoseEdge& edge, const SE2& T_world_a, const SE2& T_world_b) {
  // The factors' own error (pose_edge_factor.h), so that the chi2 reported
  // is the one the solver minimised.
  const double a[3] = {T_world_a.x(), T_world_a.y(), T_world_a.yaw()};
  const double b[3] = {T_world_b.x(), T_world_b.y(), T_world_b.yaw()};
  Eigen::Vector3d error;
  RelativePoseError(edge.T_from_to)(a, b, error.data());
  return error;
}

double PoseEdgeChi2(const PoseGraph& graph, const PoseEdge& edge) {
  const Eigen::Vector3d e = PoseEdgeError(edge, graph.poses.at(edge.from), graph.poses.at(edge.to));
  return e.dot(edge.information * e);
}

void CheckPoseGraph(const PoseGraph& graph) {
  for (size_t i = 0; i < graph.pose_edges.size(); ++i) {
    const PoseEdge& edge = graph.pose_edges[i];
    const std::string name = EdgeName("pose edge", i, edge.from, edge.to);
    if (!graph.poses.contains(edge.from) || !graph.poses.contains(edge.to)) {
      throw std::invalid_argument(name + ": names a pose vertex that does not exist");
    }
    if (edge.from == edge.to) throw std::invalid_argument(name + ": joins a pose to itself");
    if (!edge.T_from_to.translation().allFinite() || !std::isfinite(edge.T_from_to.yaw())) {
      throw std::invalid_argument(name + ": measurement is not finite");
    }
    if (!IsSymmetricPositiveDefinite<3>(edge.information)) {
      throw std::invalid_argument(name + ": information is not symmetric positive definite");
    }
  }
  for (size_t i = 0; i < graph.point_edges.size(); ++i) {
    const PointEdge& edge = graph.point_edges[i];
    const std::string name = EdgeName("point edge", i, edge.pose, edge.point);
    if (!graph.poses.contains(edge.pose) || !graph.points.contains(edge.point)) {
      throw std::invalid_argument(name + ": names a vertex that does not exist");
    }
    if (!edge.p_pose.allFinite()) throw std::invalid_argument(name + ": measurement is not finite");
    if (!IsSymmetricPositiveDefinite<2>(edge.information)) {
      throw std::invalid_argument(name + ": information is not symmetric positive definite");
    }
  }
  for (int id : graph.fixed) {
    if (!graph.poses.contains(id) && !graph.points.contains(id)) {
      throw std::invalid_argument("fixed vertex " + std::to_string(id) + " does not exist");
    }
  }
}

}  // namespace parkslam::graph
