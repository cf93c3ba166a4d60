#include "parkslam/control/trace.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "parkslam/common/angles.h"
#include "parkslam/common/cross.h"

namespace parkslam::control {
namespace {

// z of the 3D cross product: positive when b points to the left of a.
double HeadingOf(const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); }

std::vector<Eigen::Vector2d> PositionsOf(const Trajectory& trajectory) {
  std::vector<Eigen::Vector2d> points_m;
  points_m.reserve(trajectory.size());
  for (const TimedPose& pose : trajectory) points_m.push_back(pose.T_map_vehicle.translation());
  return points_m;
}

}  // namespace

Trace::Trace(const Trajectory& trajectory) : Trace(PositionsOf(trajectory)) {}

Trace::Trace(const std::vector<Eigen::Vector2d>& points_m) {
  for (const Eigen::Vector2d& p : points_m) {
    if (!p.allFinite()) throw std::invalid_argument("Trace: non-finite point");
    if (points_m_.empty() || (p - points_m_.back()).norm() >= kMinPointSpacingM) {
      points_m_.push_back(p);
    }
  }
  // Keep the true end of the drive: a dropped last point replaces the last
  // kept one when the spacing to the one before still allows it.
  if (points_m_.size() >= 2 && !points_m.empty() && points_m.back() != points_m_.back() &&
      (points_m.back() - points_m_[points_m_.size() - 2]).norm() >= kMinPointSpacingM) {
    points_m_.back() = points_m.back();
  }
  if (points_m_.size() < 2) {
    throw std::invalid_argument("Trace: fewer than 2 distinct points");
  }
  arc_lengths_m_.assign(points_m_.size(), 0.0);
  for (size_t i = 1; i < points_m_.size(); ++i) {
    arc_lengths_m_[i] = arc_lengths_m_[i - 1] + (points_m_[i] - points_m_[i - 1]).norm();
  }
  if (length_m() < kMinLengthM) {
    throw std::invalid_argument("Trace: path shorter than 1 m");
  }
}

size_t Trace::SegmentAt(double s_m) const {
  const auto after = std::upper_bound(arc_lengths_m_.begin(), arc_lengths_m_.end(), s_m);
  const auto index = static_cast<size_t>(
      std::max<std::ptrdiff_t>(0, std::distance(arc_lengths_m_.begin(), after) - 1));
  return std::min(index, points_m_.size() - 2);
}

Eigen::Vector2d Trace::Direction(size_t i) const {
  return (points_m_[i + 1] - points_m_[i]) / (arc_lengths_m_[i + 1] - arc_lengths_m_[i]);
}

Eigen::Vector2d Trace::PointAt(double s_m) const {
  const double s = std::clamp(s_m, 0.0, length_m());
  const size_t i = SegmentAt(s);
  return points_m_[i] + (s - arc_lengths_m_[i]) * Direction(i);
}

double Trace::HeadingAt(double s_m) const { return HeadingOf(Direction(SegmentAt(s_m))); }

double Trace::CurvatureAt(double s_m) const {
  // Near an end, the curvature where the whole window first fits.
  const double half_m = std::min(kCurvatureHalfWindowM, 0.5 * length_m());
  const double s = std::clamp(s_m, half_m, length_m() - half_m);
  const Eigen::Vector2d here = PointAt(s);
  // On a circle a chord's heading is the tangent at its midpoint, and the
  // midpoints of the two chords are half_m apart.
  const double heading_back = HeadingOf(here - PointAt(s - half_m));
  const double heading_ahead = HeadingOf(PointAt(s + half_m) - here);
  return AngleDiff(heading_ahead, heading_back) / half_m;
}

Trace::Projection Trace::Project(const Eigen::Vector2d& p, double s_hint_m, double window_m) const {
  const double window = std::max(0.0, window_m);
  const double lo_m = std::clamp(s_hint_m - window, 0.0, length_m());
  const double hi_m = std::clamp(s_hint_m + window, 0.0, length_m());
  const size_t last = SegmentAt(hi_m);

  size_t best_i = SegmentAt(lo_m);
  double best_t = 0.0;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (size_t i = best_i; i <= last; ++i) {
    const Eigen::Vector2d dir = Direction(i);
    const double t_lo = std::max(0.0, lo_m - arc_lengths_m_[i]);
    const double t_hi =
        std::min(arc_lengths_m_[i + 1] - arc_lengths_m_[i], hi_m - arc_lengths_m_[i]);
    const double t = std::clamp((p - points_m_[i]).dot(dir), t_lo, std::max(t_lo, t_hi));
    const double d2 = (p - (points_m_[i] + t * dir)).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best_i = i;
      best_t = t;
    }
  }

  Projection projection;
  projection.s_m = arc_lengths_m_[best_i] + best_t;
  projection.point = points_m_[best_i] + best_t * Direction(best_i);
  const Eigen::Vector2d offset = p - projection.point;
  const double segment_m = arc_lengths_m_[best_i + 1] - arc_lengths_m_[best_i];
  // At an inner vertex the offset lies between the two segment normals: its
  // length, signed by the side of the bisecting tangent.
  std::ptrdiff_t before = -1;
  if (best_t <= 0.0 && best_i > 0) before = static_cast<std::ptrdiff_t>(best_i) - 1;
  if (best_t >= segment_m && best_i + 2 < points_m_.size()) {
    before = static_cast<std::ptrdiff_t>(best_i);
  }
  if (before >= 0) {
    const auto b = static_cast<size_t>(before);
    const Eigen::Vector2d tangent = Direction(b) + Direction(b + 1);
    projection.lateral_m = std::copysign(offset.norm(), Cross(tangent, offset));
  } else {
    projection.lateral_m = Cross(Direction(best_i), offset);
  }
  return projection;
}

Trace::Projection Trace::ProjectGlobal(const Eigen::Vector2d& p) const {
  return Project(p, 0.0, length_m());
}

}  // namespace parkslam::control
