#include "parkslam/common/convex_polygon.h"

#include <cmath>

namespace parkslam {
namespace {

double SignedArea(const std::vector<Eigen::Vector2d>& polygon) {
  double twice = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * twice;
}

// Positive on the left of the directed line a -> b.
double Side(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
}

}  // namespace

double PolygonArea(const std::vector<Eigen::Vector2d>& polygon) {
  return std::abs(SignedArea(polygon));
}

double ConvexOverlapArea(const std::vector<Eigen::Vector2d>& subject,
                         const std::vector<Eigen::Vector2d>& clip) {
  if (subject.size() < 3 || clip.size() < 3) return 0.0;
  // Keep the left of each clip edge: run the clip polygon counter-clockwise.
  std::vector<Eigen::Vector2d> edges = clip;
  if (SignedArea(edges) < 0.0) edges.assign(clip.rbegin(), clip.rend());
  std::vector<Eigen::Vector2d> out = subject;
  for (size_t e = 0; e < edges.size() && !out.empty(); ++e) {
    const Eigen::Vector2d& a = edges[e];
    const Eigen::Vector2d& b = edges[(e + 1) % edges.size()];
    const std::vector<Eigen::Vector2d> in = out;
    out.clear();
    for (size_t i = 0; i < in.size(); ++i) {
      const Eigen::Vector2d& p = in[i];
      const Eigen::Vector2d& q = in[(i + 1) % in.size()];
      const double sp = Side(a, b, p), sq = Side(a, b, q);
      if (sp >= 0.0) out.push_back(p);
      if ((sp >= 0.0) != (sq >= 0.0)) out.push_back(p + (q - p) * (sp / (sp - sq)));
    }
  }
  return out.size() < 3 ? 0.0 : PolygonArea(out);
}

}  // namespace parkslam
