#ifndef PARKSLAM_SENSOR_VEHICLE_H_
#define PARKSLAM_SENSOR_VEHICLE_H_

#include <string>

namespace parkslam {

// Geometry of the vehicle that the sensors are mounted on. The vehicle frame
// has its origin at the centre of the rear axle on the ground, x forward,
// y left (DESIGN.md 3).
struct VehicleParameters {
  double wheelbase_m = 2.7;
  double steering_ratio = 15.0;            // steering-wheel angle / road-wheel angle
  double max_road_wheel_angle_rad = 0.61;  // 35 degrees
  double max_road_wheel_rate_radps = 0.5;
  double length_m = 4.7;
  double width_m = 1.85;
  double rear_overhang_m = 1.0;  // rear bumper behind the rear axle

  bool IsValid(std::string* error) const;

  // The field list, walked by the YAML loader (io/scenario_yaml.h).
  template <typename V>
  void VisitFields(V& v) {
    v("wheelbase_m", wheelbase_m);
    v("steering_ratio", steering_ratio);
    v("max_road_wheel_angle_rad", max_road_wheel_angle_rad);
    v("max_road_wheel_rate_radps", max_road_wheel_rate_radps);
    v("length_m", length_m);
    v("width_m", width_m);
    v("rear_overhang_m", rear_overhang_m);
  }
};

}  // namespace parkslam

#endif  // PARKSLAM_SENSOR_VEHICLE_H_
