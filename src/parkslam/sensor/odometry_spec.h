#ifndef PARKSLAM_SENSOR_ODOMETRY_SPEC_H_
#define PARKSLAM_SENSOR_ODOMETRY_SPEC_H_

// What a datasheet says of the odometry sensors (paper III-C: "steering
// wheel angle, car speed and the compass readings from a cheap IMU"): their
// rates and noise. A dataset carries it (`sensors.odometry` of dataset.yaml);
// the EKF is tuned from it (odometry::EkfOptionsFromSpec), and the simulator
// draws its noise from it.

#include <string>

namespace parkslam {

struct OdometrySensorSpec {
  double wheel_rate_hz = 50.0;
  double wheel_speed_sigma_mps = 0.02;
  double wheel_speed_scale_sigma = 0.003;  // per drive, relative
  double steering_rate_hz = 50.0;
  double steering_wheel_sigma_rad = 0.01;
  double imu_rate_hz = 100.0;
  double gyro_sigma_radps = 0.005;
  double gyro_bias_sigma_radps = 0.003;  // initial bias, per drive
  double gyro_bias_walk_radps_per_sqrt_s = 0.00005;
  double heading_sigma_rad = 0.01;
  double heading_bias_sigma_rad = 0.02;  // initial bias, per drive
  double heading_bias_walk_rad_per_sqrt_s = 0.0005;

  // Checks every field against common/plausible_ranges.h; on failure names
  // it in *error: "sensors.odometry.imu_rate_hz: must be in [1, 1000] Hz".
  bool IsValid(std::string* error) const;

  template <typename V>
  void VisitFields(V& v) {
    v("wheel_rate_hz", wheel_rate_hz);
    v("wheel_speed_sigma_mps", wheel_speed_sigma_mps);
    v("wheel_speed_scale_sigma", wheel_speed_scale_sigma);
    v("steering_rate_hz", steering_rate_hz);
    v("steering_wheel_sigma_rad", steering_wheel_sigma_rad);
    v("imu_rate_hz", imu_rate_hz);
    v("gyro_sigma_radps", gyro_sigma_radps);
    v("gyro_bias_sigma_radps", gyro_bias_sigma_radps);
    v("gyro_bias_walk_radps_per_sqrt_s", gyro_bias_walk_radps_per_sqrt_s);
    v("heading_sigma_rad", heading_sigma_rad);
    v("heading_bias_sigma_rad", heading_bias_sigma_rad);
    v("heading_bias_walk_rad_per_sqrt_s", heading_bias_walk_rad_per_sqrt_s);
  }
};

}  // namespace parkslam

#endif  // PARKSLAM_SENSOR_ODOMETRY_SPEC_H_
