#include "parkslam/sensor/vehicle.h"

#include <cmath>

namespace parkslam {

bool VehicleParameters::IsValid(std::string* error) const {
  auto fail = [error](const char* message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (!(wheelbase_m > 0.5 && wheelbase_m < 10.0))
    return fail("vehicle.wheelbase_m must be in (0.5, 10)");
  if (!(steering_ratio > 1.0 && steering_ratio < 50.0))
    return fail("vehicle.steering_ratio must be in (1, 50)");
  if (!(max_road_wheel_angle_rad > 0.05 && max_road_wheel_angle_rad < 1.2))
    return fail("vehicle.max_road_wheel_angle_rad must be in (0.05, 1.2)");
  if (!(max_road_wheel_rate_radps > 0.0))
    return fail("vehicle.max_road_wheel_rate_radps must be positive");
  if (!(length_m > 0.0 && width_m > 0.0 && rear_overhang_m >= 0.0 &&
        rear_overhang_m < length_m))
    return fail("vehicle dimensions must be positive, rear_overhang_m < length_m");
  return true;
}

}  // namespace parkslam
