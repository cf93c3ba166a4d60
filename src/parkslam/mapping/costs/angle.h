#ifndef PARKSLAM_MAPPING_COSTS_ANGLE_H_
#define PARKSLAM_MAPPING_COSTS_ANGLE_H_

// Angle wrapping for residuals and the manifold of a planar pose block
// (DESIGN.md section 3: yaw normalized to (-pi, pi]).
//
//   WrapAngle(a) = a - 2 pi ceil((a - pi) / (2 pi))   in (-pi, pi]
//
// The ceil term is piecewise constant, so d WrapAngle / d a = 1 everywhere
// except at the wrap itself; for a ceres::Jet the ceil carries no derivative
// (ceres::ceil returns a Jet with a zero infinitesimal part), so automatic
// differentiation sees the identity, as it should.
//
// Pose2Manifold is the manifold of a block {x_m, y_m, yaw_rad} (a vehicle pose
// T_map_vehicle, or a tag {x_m, y_m, yaw_rad}):
//
//   x [+] delta = (x0 + d0, x1 + d1, WrapAngle(x2 + d2))
//   y [-] x     = (y0 - x0, y1 - x1, WrapAngle(y2 - x2))
//
// Both Jacobians are the identity (the tangent space is R^2 x R, the yaw chart
// is the angle itself), so it is written as a ceres::Manifold with exact
// Jacobians rather than an AutoDiffManifold.

#include <ceres/manifold.h>

#include <cmath>
#include <numbers>

namespace parkslam::mapping {

// Wraps an angle (a double or a ceres::Jet) into (-pi, pi]. Agrees with
// parkslam::NormalizeAngle on doubles (both map -pi to pi).
template <typename T>
T WrapAngle(const T& angle_rad) {
  using std::ceil;  // ceres::ceil is found by argument-dependent lookup.
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  return angle_rad - kTwoPi * ceil((angle_rad - std::numbers::pi) / kTwoPi);
}

// The manifold of a 3-vector {x_m, y_m, yaw_rad}: Euclidean in x and y, the
// circle in yaw (kept in (-pi, pi]). Usable for pose blocks and tag blocks.
class Pose2Manifold final : public ceres::Manifold {
 public:
  static constexpr int kSize = 3;

  int AmbientSize() const override { return kSize; }
  int TangentSize() const override { return kSize; }

  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    x_plus_delta[0] = x[0] + delta[0];
    x_plus_delta[1] = x[1] + delta[1];
    x_plus_delta[2] = WrapAngle(x[2] + delta[2]);
    return true;
  }

  // Row-major 3x3 identity.
  bool PlusJacobian(const double* /*x*/, double* jacobian) const override {
    SetIdentity(jacobian);
    return true;
  }

  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    y_minus_x[0] = y[0] - x[0];
    y_minus_x[1] = y[1] - x[1];
    y_minus_x[2] = WrapAngle(y[2] - x[2]);
    return true;
  }

  bool MinusJacobian(const double* /*x*/, double* jacobian) const override {
    SetIdentity(jacobian);
    return true;
  }

 private:
  static void SetIdentity(double* jacobian) {
    for (int r = 0; r < kSize; ++r) {
      for (int c = 0; c < kSize; ++c) jacobian[r * kSize + c] = r == c ? 1.0 : 0.0;
    }
  }
};

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_COSTS_ANGLE_H_
