#include "parkslam/common/alignment.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace parkslam {
namespace {

Eigen::Vector2d Centroid(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

}  // namespace

SE2 AlignPointSets(const std::vector<Eigen::Vector2d>& source,
                   const std::vector<Eigen::Vector2d>& target) {
  if (source.size() != target.size()) {
    throw std::invalid_argument("AlignPointSets: source has " + std::to_string(source.size()) +
                                " points but target has " + std::to_string(target.size()));
  }
  if (source.size() < 2) {
    throw std::invalid_argument("AlignPointSets: needs at least 2 points");
  }
  const Eigen::Vector2d source_centroid = Centroid(source);
  const Eigen::Vector2d target_centroid = Centroid(target);

  // For centred points s, t the cost is minimised by the angle maximising
  // sum t . (R s) = cos(a) sum(s . t) + sin(a) sum(s x t).
  double sum_dot = 0.0;
  double sum_cross = 0.0;
  for (size_t i = 0; i < source.size(); ++i) {
    const Eigen::Vector2d s = source[i] - source_centroid;
    const Eigen::Vector2d t = target[i] - target_centroid;
    sum_dot += s.dot(t);
    sum_cross += s.x() * t.y() - s.y() * t.x();
  }
  const double yaw_rad = std::atan2(sum_cross, sum_dot);
  const SE2 rotation_only(Eigen::Vector2d::Zero(), yaw_rad);
  return SE2(target_centroid - rotation_only * source_centroid, yaw_rad);
}

}  // namespace parkslam
