#ifndef PARKSLAM_GRAPH_POSE_GRAPH_H_
#define PARKSLAM_GRAPH_POSE_GRAPH_H_

// A planar pose graph, the robust back end of the mapper on its own (paper
// section III-C, "Optimization Framework"): poses, optional point landmarks,
// relative-pose edges and pose-to-point edges, each with its information
// matrix. The layout follows the g2o 2D types (VERTEX_SE2, EDGE_SE2,
// VERTEX_XY, EDGE_SE2_XY, FIX) so that the field's benchmark graphs can be
// read as they are (io/g2o.h).

#include <Eigen/Core>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "parkslam/common/se2.h"

namespace parkslam::graph {

// Measured pose of `to` in the frame of `from`: T_from_to.
struct PoseEdge {
  int from = 0;
  int to = 0;
  SE2 T_from_to;
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();  // over (x_m, y_m, yaw_rad)
};

// Measured position of point `point` in the frame of pose `pose`.
struct PointEdge {
  int pose = 0;
  int point = 0;
  Eigen::Vector2d p_pose = Eigen::Vector2d::Zero();
  Eigen::Matrix2d information = Eigen::Matrix2d::Identity();
};

// The null hypothesis a file gave its loop closures (g2o's
// EDGE_SE2_MIXTURE): its weight against the closure's own component and the
// scale of its information against the closure's.
struct NullHypothesis {
  double weight = 0.0;
  double information_scale = 0.0;
};

struct PoseGraph {
  std::map<int, SE2> poses;               // T_world_pose, by vertex id
  std::map<int, Eigen::Vector2d> points;  // p_world, by vertex id
  std::vector<PoseEdge> pose_edges;
  std::vector<PointEdge> point_edges;
  std::set<int> fixed;  // vertex ids held constant
  std::optional<NullHypothesis> file_null;
};

// An edge between consecutive pose ids is odometry; every other pose edge is
// a loop closure, which may be wrong.
inline bool IsOdometry(const PoseEdge& edge) {
  return edge.to - edge.from == 1 || edge.from - edge.to == 1;
}

// The residual of a pose edge at poses T_world_a (from) and T_world_b (to):
//   e = [ R(yaw_z)^T (R(yaw_a)^T (t_b - t_a) - t_z) ; wrap(yaw_b - yaw_a - yaw_z) ]
// (g2o's Z^-1 (A^-1 B); computed by pose_edge_factor.h's RelativePoseError).
Eigen::Vector3d PoseEdgeError(const PoseEdge& edge, const SE2& T_world_a, const SE2& T_world_b);

// e^T Omega e of a pose edge at the graph's current estimates.
double PoseEdgeChi2(const PoseGraph& graph, const PoseEdge& edge);

// Throws std::invalid_argument naming the first edge whose vertices are
// missing, whose information is not symmetric positive definite or not
// finite, or a fixed id that is no vertex.
void CheckPoseGraph(const PoseGraph& graph);

}  // namespace parkslam::graph

#endif  // PARKSLAM_GRAPH_POSE_GRAPH_H_
