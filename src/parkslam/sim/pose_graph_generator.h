#ifndef PARKSLAM_SIM_POSE_GRAPH_GENERATOR_H_
#define PARKSLAM_SIM_POSE_GRAPH_GENERATOR_H_

// Synthetic planar pose graphs with known truth, in the style of the field's
// standard benchmarks (Olson's Manhattan world M3500; rings of repeated laps),
// and the outlier loop closures of robust-SLAM evaluations (Sunderhauf &
// Protzel 2012): random ones, and groups of mutually consistent wrong ones.
//
// Every measurement is the true relative pose plus Gaussian noise of the
// stated sigmas; the information matrices are the inverse of that noise, so
// that e^T Omega e of a true edge at the truth is chi-square with 3 degrees
// of freedom. The initial estimates are dead reckoning: the noisy odometry
// composed from the true first pose.

#include <cstdint>
#include <map>

#include "parkslam/common/random.h"
#include "parkslam/common/se2.h"
#include "parkslam/graph/pose_graph.h"

namespace parkslam::sim {

enum class GraphWorld { kManhattan, kRing };

struct SyntheticGraphOptions {
  GraphWorld world = GraphWorld::kManhattan;
  int poses = 3500;
  double sigma_xy_m = 0.05;
  double sigma_yaw_rad = 0.01;
  // Chance that a pose revisiting a place gets a (true) loop closure to one
  // of its earlier visits.
  double closure_probability = 0.5;
  // Manhattan: 1 m steps on a grid of grid_cells x grid_cells, turning left
  // or right at a crossing with turn_probability each.
  int grid_cells = 40;
  double turn_probability = 0.2;
  // Ring: laps of a circle.
  int poses_per_lap = 200;
  double radius_m = 30.0;
};

struct SyntheticGraph {
  graph::PoseGraph graph;
  std::map<int, SE2> truth;  // T_world_pose by vertex id
};

// Throws std::invalid_argument for options out of range.
SyntheticGraph MakeSyntheticGraph(const SyntheticGraphOptions& options, std::uint64_t seed);

// Adds `count` loop closures between random pose pairs (not consecutive)
// whose measurements are random (translation within 10 m, any heading) and
// whose information is that of a true closure. Returns how many were added.
int AddRandomOutliers(int count, Random* random, graph::PoseGraph* graph);

// Adds `count` local wrong closures (Sunderhauf & Protzel 2012's "local"
// outliers): between a random pose i and pose i + k, k drawn from
// [2, window], with a measurement near the true one, the true relative pose
// moved by a random offset of 0.5 to 2 m and up to 0.5 rad. Such closures fit
// the trajectory nearly as well as true ones. Returns how many were added.
int AddLocalOutliers(int count, int window, const std::map<int, SE2>& truth, Random* random,
                     graph::PoseGraph* graph);

// Adds `groups` groups of `group_size` closures each: pose i + k claims to be
// seen from pose j + k for k = 0..group_size-1, with measurements that agree
// with each other and with odometry, as if place i were place j (perceptual
// aliasing). Returns how many closures were added.
int AddGroupedOutliers(int groups, int group_size, const std::map<int, SE2>& truth, Random* random,
                       graph::PoseGraph* graph);

}  // namespace parkslam::sim

#endif  // PARKSLAM_SIM_POSE_GRAPH_GENERATOR_H_
