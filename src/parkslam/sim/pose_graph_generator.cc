#include "parkslam/sim/pose_graph_generator.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

namespace parkslam::sim {
namespace {

SE2 Noisy(const SE2& T, const SyntheticGraphOptions& o, Random* random) {
  return T * SE2(random->Gaussian(o.sigma_xy_m), random->Gaussian(o.sigma_xy_m),
                 random->Gaussian(o.sigma_yaw_rad));
}

Eigen::Matrix3d Information(const SyntheticGraphOptions& o) {
  const double ixy = 1.0 / (o.sigma_xy_m * o.sigma_xy_m);
  return Eigen::Vector3d(ixy, ixy, 1.0 / (o.sigma_yaw_rad * o.sigma_yaw_rad)).asDiagonal();
}

// The true poses: a walk on the grid's crossings, or laps of a circle.
std::vector<SE2> TruePoses(const SyntheticGraphOptions& o, Random* random) {
  std::vector<SE2> poses;
  poses.reserve(o.poses);
  if (o.world == GraphWorld::kRing) {
    for (int i = 0; i < o.poses; ++i) {
      const double angle = 2.0 * std::numbers::pi * i / o.poses_per_lap;
      poses.emplace_back(o.radius_m * std::cos(angle), o.radius_m * std::sin(angle),
                         angle + 0.5 * std::numbers::pi);
    }
    return poses;
  }
  int x = o.grid_cells / 2, y = o.grid_cells / 2, heading = 0;  // heading in quarter turns
  const int dx[4] = {1, 0, -1, 0}, dy[4] = {0, 1, 0, -1};
  auto inside = [&](int h) {
    const int nx = x + dx[h], ny = y + dy[h];
    return nx >= 0 && ny >= 0 && nx < o.grid_cells && ny < o.grid_cells;
  };
  for (int i = 0; i < o.poses; ++i) {
    poses.emplace_back(x, y, heading * 0.5 * std::numbers::pi);
    const double u = random->Uniform();
    if (u < o.turn_probability) {
      heading = (heading + 1) % 4;
    } else if (u < 2.0 * o.turn_probability) {
      heading = (heading + 3) % 4;
    }
    // At the border, turn until the way is free (a U-turn at a corner).
    for (int tries = 0; !inside(heading) && tries < 4; ++tries) {
      heading = (heading + (random->Bernoulli(0.5) ? 1 : 3)) % 4;
    }
    x += dx[heading];
    y += dy[heading];
  }
  return poses;
}

}  // namespace

SyntheticGraph MakeSyntheticGraph(const SyntheticGraphOptions& o, std::uint64_t seed) {
  if (o.poses < 2 || o.poses > 1000000) throw std::invalid_argument("poses must be in [2, 1e6]");
  if (!(o.sigma_xy_m > 0.0 && o.sigma_xy_m < 10.0) ||
      !(o.sigma_yaw_rad > 0.0 && o.sigma_yaw_rad < 1.0)) {
    throw std::invalid_argument("sigmas must be in (0, 10) m and (0, 1) rad");
  }
  if (!(o.closure_probability >= 0.0 && o.closure_probability <= 1.0) ||
      !(o.turn_probability >= 0.0 && o.turn_probability <= 0.5)) {
    throw std::invalid_argument("closure_probability in [0, 1], turn_probability in [0, 0.5]");
  }
  if (o.grid_cells < 2 || o.poses_per_lap < 3 || !(o.radius_m > 0.0)) {
    throw std::invalid_argument("grid_cells >= 2, poses_per_lap >= 3, radius_m > 0");
  }
  Random random(seed);
  const std::vector<SE2> truth = TruePoses(o, &random);
  const Eigen::Matrix3d information = Information(o);
  SyntheticGraph out;
  out.graph.poses[0] = truth[0];
  out.truth[0] = truth[0];
  // Places visited so far: rounded position -> pose ids there.
  std::map<std::pair<long, long>, std::vector<int>> visits;
  auto place = [&](const SE2& T) {
    return std::make_pair(std::lround(T.x() * 2.0), std::lround(T.y() * 2.0));
  };
  visits[place(truth[0])].push_back(0);
  for (int i = 1; i < o.poses; ++i) {
    out.truth[i] = truth[i];
    const SE2 odometry = Noisy(truth[i - 1].inverse() * truth[i], o, &random);
    out.graph.poses[i] = out.graph.poses[i - 1] * odometry;
    out.graph.pose_edges.push_back({i - 1, i, odometry, information});
    std::vector<int>& here = visits[place(truth[i])];
    std::vector<int> earlier;
    for (int j : here) {
      if (j < i - 1) earlier.push_back(j);
    }
    if (!earlier.empty() && random.Bernoulli(o.closure_probability)) {
      const int j = earlier[random.Index(earlier.size())];
      out.graph.pose_edges.push_back(
          {j, i, Noisy(truth[j].inverse() * truth[i], o, &random), information});
    }
    here.push_back(i);
  }
  out.graph.fixed.insert(0);
  return out;
}

namespace {

Eigen::Matrix3d ClosureInformation(const graph::PoseGraph& graph) {
  for (const graph::PoseEdge& e : graph.pose_edges) {
    if (!graph::IsOdometry(e)) return e.information;
  }
  return graph.pose_edges.empty() ? Eigen::Matrix3d::Identity() : graph.pose_edges[0].information;
}

std::pair<int, int> RandomPair(int n, Random* random) {
  while (true) {
    const int a = static_cast<int>(random->Index(n));
    const int b = static_cast<int>(random->Index(n));
    if (std::abs(a - b) > 1) return {std::min(a, b), std::max(a, b)};
  }
}

}  // namespace

int AddRandomOutliers(int count, Random* random, graph::PoseGraph* graph) {
  const int n = static_cast<int>(graph->poses.size());
  if (n < 3 || count <= 0) return 0;
  const Eigen::Matrix3d information = ClosureInformation(*graph);
  for (int k = 0; k < count; ++k) {
    const auto [a, b] = RandomPair(n, random);
    const SE2 measured(random->Uniform(-10.0, 10.0), random->Uniform(-10.0, 10.0),
                       random->Uniform(-std::numbers::pi, std::numbers::pi));
    graph->pose_edges.push_back({a, b, measured, information});
  }
  return count;
}

int AddLocalOutliers(int count, int window, const std::map<int, SE2>& truth, Random* random,
                     graph::PoseGraph* graph) {
  const int n = static_cast<int>(truth.size());
  if (count <= 0 || window < 2 || n < window + 1) return 0;
  const Eigen::Matrix3d information = ClosureInformation(*graph);
  for (int added = 0; added < count; ++added) {
    const int i = static_cast<int>(random->Index(n - window));
    const int j = i + 2 + static_cast<int>(random->Index(window - 1));
    const double offset_m = random->Uniform(0.5, 2.0);
    const double direction = random->Uniform(-std::numbers::pi, std::numbers::pi);
    const SE2 offset(offset_m * std::cos(direction), offset_m * std::sin(direction),
                     random->Uniform(-0.5, 0.5));
    graph->pose_edges.push_back({i, j, truth.at(i).inverse() * truth.at(j) * offset, information});
  }
  return count;
}

int AddGroupedOutliers(int groups, int group_size, const std::map<int, SE2>& truth, Random* random,
                       graph::PoseGraph* graph) {
  const int n = static_cast<int>(truth.size());
  if (groups <= 0 || group_size <= 0 || n < 2 * group_size + 2) return 0;
  const Eigen::Matrix3d information = ClosureInformation(*graph);
  int added = 0;
  for (int g = 0; g < groups; ++g) {
    const int i = static_cast<int>(random->Index(n - group_size));
    int j = static_cast<int>(random->Index(n - group_size));
    while (std::abs(i - j) <= group_size) j = static_cast<int>(random->Index(n - group_size));
    // Pretend pose j stands where pose i stands: the place seen from j + k is
    // the one around i, so T_(i+k)_(j+k) = T_(i+k)^-1 T_i T_j^-1 T_(j+k).
    const SE2 alias = truth.at(i) * truth.at(j).inverse();
    for (int k = 0; k < group_size; ++k) {
      const SE2 claimed = truth.at(i + k).inverse() * alias * truth.at(j + k);
      graph->pose_edges.push_back({i + k, j + k, claimed, information});
      ++added;
    }
  }
  return added;
}

}  // namespace parkslam::sim
