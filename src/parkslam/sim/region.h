#ifndef PARKSLAM_SIM_REGION_H_
#define PARKSLAM_SIM_REGION_H_

#include <Eigen/Core>

namespace parkslam::sim {

// An axis-aligned rectangle of the map frame.
struct RegionConfig {
  double min_x_m = 0.0, min_y_m = 0.0, max_x_m = 0.0, max_y_m = 0.0;

  bool Contains(const Eigen::Vector2d& p) const {
    return p.x() >= min_x_m && p.x() <= max_x_m && p.y() >= min_y_m && p.y() <= max_y_m;
  }
  template <typename V>
  void VisitFields(V& v) {
    v("min_x_m", min_x_m);
    v("min_y_m", min_y_m);
    v("max_x_m", max_x_m);
    v("max_y_m", max_y_m);
  }
};

}  // namespace parkslam::sim

#endif  // PARKSLAM_SIM_REGION_H_
