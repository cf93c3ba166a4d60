#ifndef PARKSLAM_COMMON_ANGLES_H_
#define PARKSLAM_COMMON_ANGLES_H_

#include <cmath>
#include <numbers>

namespace parkslam {

inline constexpr double kPi = std::numbers::pi;

inline constexpr double DegToRad(double deg) { return deg * kPi / 180.0; }
inline constexpr double RadToDeg(double rad) { return rad * 180.0 / kPi; }

// Wraps an angle into (-pi, pi].
inline double NormalizeAngle(double angle_rad) {
  double a = std::fmod(angle_rad, 2.0 * kPi);  // (-2pi, 2pi)
  if (a <= -kPi) a += 2.0 * kPi;
  if (a > kPi) a -= 2.0 * kPi;
  return a;
}

// The signed difference a - b wrapped into (-pi, pi].
inline double AngleDiff(double a_rad, double b_rad) { return NormalizeAngle(a_rad - b_rad); }

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_ANGLES_H_
