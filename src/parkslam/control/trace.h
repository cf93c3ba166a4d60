#ifndef PARKSLAM_CONTROL_TRACE_H_
#define PARKSLAM_CONTROL_TRACE_H_

#include <Eigen/Core>
#include <vector>

#include "parkslam/common/trajectory.h"

namespace parkslam::control {

// A recorded drive turned into a path to follow (paper IV-B: a human drive is
// recorded, then the car follows that trace autonomously). A polyline through
// the positions of the poses, parameterised by arc length s_m in [0, length_m].
// Queries cost O(log n + window) through the precomputed cumulative lengths.
class Trace {
 public:
  // Consecutive points closer than this to the last kept point are dropped.
  static constexpr double kMinPointSpacingM = 0.05;
  static constexpr double kMinLengthM = 1.0;
  // Half-width of the arc-length window of CurvatureAt.
  static constexpr double kCurvatureHalfWindowM = 1.0;

  // Throws std::invalid_argument when fewer than 2 distinct points remain or
  // the path is shorter than kMinLengthM.
  explicit Trace(const Trajectory& trajectory);
  explicit Trace(const std::vector<Eigen::Vector2d>& points_m);

  double length_m() const { return arc_lengths_m_.back(); }
  // The kept polyline vertices and their arc lengths.
  const std::vector<Eigen::Vector2d>& points_m() const { return points_m_; }
  const std::vector<double>& arc_lengths_m() const { return arc_lengths_m_; }

  // The point at arc length s_m, clamped to [0, length_m].
  Eigen::Vector2d PointAt(double s_m) const;
  // Direction of travel of the segment holding s_m (the later segment at a
  // vertex), in (-pi, pi].
  double HeadingAt(double s_m) const;
  // Signed curvature (left turn positive, 1/m): heading change between the
  // chords [s - 1 m, s] and [s, s + 1 m] over the distance between their
  // midpoints; exact on a circle. Within 1 m of an end, the value where the
  // window first fits.
  double CurvatureAt(double s_m) const;

  struct Projection {
    double s_m = 0.0;
    // Signed, left of the direction of travel positive. Beyond either end of
    // the trace, the offset perpendicular to the end segment.
    double lateral_m = 0.0;
    Eigen::Vector2d point = Eigen::Vector2d::Zero();
  };

  // The closest point on the trace within [s_hint_m - window_m, s_hint_m +
  // window_m], so a trace that passes the same place twice is followed in
  // order. O(log n + segments in the window).
  Projection Project(const Eigen::Vector2d& p, double s_hint_m, double window_m) const;
  // The closest point on the whole trace.
  Projection ProjectGlobal(const Eigen::Vector2d& p) const;

 private:
  // The segment [i, i + 1] holding s_m (clamped), the later one at a vertex.
  size_t SegmentAt(double s_m) const;
  // Unit direction of segment i.
  Eigen::Vector2d Direction(size_t i) const;

  std::vector<Eigen::Vector2d> points_m_;
  std::vector<double> arc_lengths_m_;
};

}  // namespace parkslam::control

#endif  // PARKSLAM_CONTROL_TRACE_H_
