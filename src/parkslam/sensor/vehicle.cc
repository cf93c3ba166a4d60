#include "parkslam/sensor/vehicle.h"

#include <cmath>
#include <cstdio>

#include "parkslam/common/plausible_ranges.h"

namespace parkslam {
namespace {

// "vehicle.<field> must be in (min, max)", or "(min, max]", with the
// limits of common/plausible_ranges.h.
std::string Range(const char* field, double min, double max, bool max_included = false) {
  char message[128];
  std::snprintf(message, sizeof message, "vehicle.%s must be in (%g, %g%c", field, min, max,
                max_included ? ']' : ')');
  return message;
}

}  // namespace

bool VehicleParameters::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (!(wheelbase_m > kMinWheelbase_m && wheelbase_m < kMaxWheelbase_m))
    return fail(Range("wheelbase_m", kMinWheelbase_m, kMaxWheelbase_m));
  if (!(steering_ratio > kMinSteeringRatio && steering_ratio < kMaxSteeringRatio))
    return fail(Range("steering_ratio", kMinSteeringRatio, kMaxSteeringRatio));
  if (!(max_road_wheel_angle_rad > kMinRoadWheelAngle_rad &&
        max_road_wheel_angle_rad < kMaxRoadWheelAngle_rad))
    return fail(Range("max_road_wheel_angle_rad", kMinRoadWheelAngle_rad, kMaxRoadWheelAngle_rad));
  if (!(max_road_wheel_rate_radps > 0.0 && max_road_wheel_rate_radps <= kMaxRoadWheelRate_radps))
    return fail(Range("max_road_wheel_rate_radps", 0.0, kMaxRoadWheelRate_radps, true));
  if (!(length_m > 0.0 && width_m > 0.0 && rear_overhang_m >= 0.0 && rear_overhang_m < length_m))
    return fail("vehicle dimensions must be positive, rear_overhang_m < length_m");
  if (!(length_m <= kMaxVehicleLength_m))
    return fail(Range("length_m", 0.0, kMaxVehicleLength_m, true));
  if (!(width_m <= kMaxVehicleWidth_m))
    return fail(Range("width_m", 0.0, kMaxVehicleWidth_m, true));
  return true;
}

}  // namespace parkslam
