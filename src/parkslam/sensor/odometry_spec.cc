#include "parkslam/sensor/odometry_spec.h"

#include <cstdio>

#include "parkslam/common/plausible_ranges.h"

namespace parkslam {

bool OdometrySensorSpec::IsValid(std::string* error) const {
  bool ok = true;
  // value in [min, max]; the first failure is reported.
  auto in_range = [&](double value, double min, double max, const char* field, const char* unit) {
    if (!ok || (value >= min && value <= max)) return;
    ok = false;
    if (error == nullptr) return;
    char message[192];
    std::snprintf(message, sizeof message, "sensors.odometry.%s: must be in [%g, %g]%s%s", field,
                  min, max, unit[0] != '\0' ? " " : "", unit);
    *error = message;
  };
  in_range(wheel_rate_hz, kMinSensorRate_hz, kMaxSensorRate_hz, "wheel_rate_hz", "Hz");
  in_range(steering_rate_hz, kMinSensorRate_hz, kMaxSensorRate_hz, "steering_rate_hz", "Hz");
  in_range(imu_rate_hz, kMinSensorRate_hz, kMaxSensorRate_hz, "imu_rate_hz", "Hz");
  // A noise no larger than the plausible magnitude of what it disturbs.
  in_range(wheel_speed_sigma_mps, 0.0, kMaxWheelSpeed_mps, "wheel_speed_sigma_mps", "m/s");
  in_range(wheel_speed_scale_sigma, 0.0, kMaxRelativeSigma, "wheel_speed_scale_sigma", "");
  in_range(steering_wheel_sigma_rad, 0.0, kMaxSteeringWheelAngle_rad, "steering_wheel_sigma_rad",
           "rad");
  in_range(gyro_sigma_radps, 0.0, kMaxYawRate_radps, "gyro_sigma_radps", "rad/s");
  in_range(gyro_bias_sigma_radps, 0.0, kMaxYawRate_radps, "gyro_bias_sigma_radps", "rad/s");
  in_range(gyro_bias_walk_radps_per_sqrt_s, 0.0, kMaxYawRate_radps,
           "gyro_bias_walk_radps_per_sqrt_s", "rad/s/sqrt(s)");
  in_range(heading_sigma_rad, 0.0, kMaxAngleSigma_rad, "heading_sigma_rad", "rad");
  in_range(heading_bias_sigma_rad, 0.0, kMaxAngleSigma_rad, "heading_bias_sigma_rad", "rad");
  in_range(heading_bias_walk_rad_per_sqrt_s, 0.0, kMaxAngleSigma_rad,
           "heading_bias_walk_rad_per_sqrt_s", "rad/sqrt(s)");
  return ok;
}

}  // namespace parkslam
