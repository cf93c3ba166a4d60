#ifndef PARKSLAM_COMMON_CONVEX_POLYGON_H_
#define PARKSLAM_COMMON_CONVEX_POLYGON_H_

#include <Eigen/Core>
#include <vector>

namespace parkslam {

// The area of a simple polygon by the shoelace formula,
//   A = 1/2 |sum_i (x_i y_{i+1} - x_{i+1} y_i)|,
// whichever way round its vertices run.
double PolygonArea(const std::vector<Eigen::Vector2d>& polygon);

// The area two convex polygons share: `subject` clipped by each edge of
// `clip` in turn (Sutherland-Hodgman), then the shoelace formula. Either
// may run clockwise or counter-clockwise; fewer than 3 vertices share
// nothing.
double ConvexOverlapArea(const std::vector<Eigen::Vector2d>& subject,
                         const std::vector<Eigen::Vector2d>& clip);

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_CONVEX_POLYGON_H_
