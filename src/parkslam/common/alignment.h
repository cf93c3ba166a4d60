#ifndef PARKSLAM_COMMON_ALIGNMENT_H_
#define PARKSLAM_COMMON_ALIGNMENT_H_

#include <Eigen/Core>
#include <vector>

#include "parkslam/common/se2.h"

namespace parkslam {

// The rigid transform T (rotation and translation, no scale) minimising
//   sum_i || target_i - T * source_i ||^2,
// in closed form (Umeyama 1991 restricted to the plane: the rotation angle is
// atan2 of the antisymmetric and symmetric parts of the cross-covariance of
// the centred sets). With source in frame b and target in frame a the result
// is T_a_b. Throws std::invalid_argument unless both sets hold the same
// number of points, at least 2.
SE2 AlignPointSets(const std::vector<Eigen::Vector2d>& source,
                   const std::vector<Eigen::Vector2d>& target);

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_ALIGNMENT_H_
