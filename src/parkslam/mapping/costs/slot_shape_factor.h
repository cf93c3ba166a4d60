#ifndef PARKSLAM_MAPPING_COSTS_SLOT_SHAPE_FACTOR_H_
#define PARKSLAM_MAPPING_COSTS_SLOT_SHAPE_FACTOR_H_

// The shape constraint that ties the four corner landmarks of one parking slot
// together (section III-A: "each point is connected with other three by a
// rectangular constraint, according to an angular constraint of high
// confidence and a distance constraint with relatively lower confidence").
// Generalized from the rectangle to a parallelogram for angled slots.
//
// Blocks: c0, c1, c2, c3 = {x, y} (map frame), counter-clockwise; c0-c1 is the
// entrance line, c2 lies behind c1 and c3 behind c0:
//
//        c3 ------- c2
//        /          /        interior angle at c0 and c2: theta
//       /          /         interior angle at c1 and c3: pi - theta
//     c0 ------- c1          (theta = pi/2 for perpendicular and parallel slots)
//        entrance
//
// Interior angle at corner k, between the edge to the next corner and the
// edge to the previous corner (indices mod 4), measured counter-clockwise:
//   a = c_{k+1} - c_k,  b = c_{k-1} - c_k,
//   phi_k = atan2(a_x b_y - a_y b_x, a . b)
// Residuals (8):
//   r_k     = wrap(phi_k - theta_k) / sigma_angle,  k = 0..3,
//             theta_0 = theta_2 = theta, theta_1 = theta_3 = pi - theta
//   r_4 = (|c1 - c0| - width) / sigma_length     (entrance line)
//   r_5 = (|c2 - c3| - width) / sigma_length     (back line)
//   r_6 = (|c3 - c0| - depth) / sigma_length     (side at c0)
//   r_7 = (|c2 - c1| - depth) / sigma_length     (side at c1)
// A clockwise (mirrored) quadrilateral gives phi_k near -theta_k, so its
// angle residuals are large: the order of the corners matters.

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "parkslam/mapping/costs/angle.h"
#include "parkslam/mapping/costs/cost_util.h"

namespace parkslam::mapping {

class SlotShapeFactor {
 public:
  static constexpr int kNumResiduals = 8;

  // angle_rad: interior angle at c0 and c2, in (0, pi). width_m: entrance
  // length |c1 - c0|; depth_m: side length |c3 - c0|. Throws
  // std::invalid_argument for values out of range.
  SlotShapeFactor(double angle_rad, double width_m, double depth_m, double angle_sigma_rad,
                  double length_sigma_m)
      : angle_rad_(CheckedAngle(angle_rad)),
        width_m_(CheckedSigma(width_m, "width_m")),
        depth_m_(CheckedSigma(depth_m, "depth_m")),
        inverse_angle_sigma_(1.0 / CheckedSigma(angle_sigma_rad, "angle_sigma_rad")),
        inverse_length_sigma_(1.0 / CheckedSigma(length_sigma_m, "length_sigma_m")) {}

  template <typename T>
  bool operator()(const T* c0, const T* c1, const T* c2, const T* c3, T* residuals) const {
    using std::atan2;
    const T* const corners[4] = {c0, c1, c2, c3};
    for (int k = 0; k < 4; ++k) {
      const T* here = corners[k];
      const T* next = corners[(k + 1) % 4];
      const T* prev = corners[(k + 3) % 4];
      const T ax = next[0] - here[0], ay = next[1] - here[1];
      const T bx = prev[0] - here[0], by = prev[1] - here[1];
      const T interior = atan2(ax * by - ay * bx, ax * bx + ay * by);
      const double expected = k % 2 == 0 ? angle_rad_ : std::numbers::pi - angle_rad_;
      residuals[k] = WrapAngle(interior - T(expected)) * inverse_angle_sigma_;
    }
    residuals[4] = (Distance(c0, c1) - T(width_m_)) * inverse_length_sigma_;
    residuals[5] = (Distance(c3, c2) - T(width_m_)) * inverse_length_sigma_;
    residuals[6] = (Distance(c0, c3) - T(depth_m_)) * inverse_length_sigma_;
    residuals[7] = (Distance(c1, c2) - T(depth_m_)) * inverse_length_sigma_;
    return true;
  }

  static ceres::CostFunction* Create(double angle_rad, double width_m, double depth_m,
                                     double angle_sigma_rad, double length_sigma_m) {
    return new ceres::AutoDiffCostFunction<SlotShapeFactor, kNumResiduals, 2, 2, 2, 2>(
        new SlotShapeFactor(angle_rad, width_m, depth_m, angle_sigma_rad, length_sigma_m));
  }

 private:
  // Not differentiable where the two corners coincide; a detected slot never
  // has coincident corners.
  template <typename T>
  static T Distance(const T* a, const T* b) {
    using std::sqrt;
    const T dx = b[0] - a[0], dy = b[1] - a[1];
    return sqrt(dx * dx + dy * dy);
  }

  static double CheckedAngle(double angle_rad) {
    if (!(angle_rad > 0.0 && angle_rad < std::numbers::pi)) {
      throw std::invalid_argument("angle_rad must lie in (0, pi)");
    }
    return angle_rad;
  }

  double angle_rad_;
  double width_m_;
  double depth_m_;
  double inverse_angle_sigma_;
  double inverse_length_sigma_;
};

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_COSTS_SLOT_SHAPE_FACTOR_H_
