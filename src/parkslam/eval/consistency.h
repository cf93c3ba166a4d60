#ifndef PARKSLAM_EVAL_CONSISTENCY_H_
#define PARKSLAM_EVAL_CONSISTENCY_H_

// Filter consistency checks (Bar-Shalom, Li, Kirubarajan, "Estimation with
// Applications to Tracking and Navigation", 2001, section 5.4.2).

#include <Eigen/Core>
#include <vector>

#include "parkslam/common/chi_square.h"

namespace parkslam::eval {

// Normalised estimation error squared, error^T covariance^-1 error, for an
// error over (x_m, y_m, yaw_rad) whose yaw the caller has already wrapped.
// The covariance must be symmetric positive definite.
double Nees(const Eigen::Vector3d& error, const Eigen::Matrix3d& covariance);

struct NeesBand {
  double lower = 0.0;
  double upper = 0.0;
};

// Two-sided confidence band for the NEES averaged over `runs` independent
// runs of a dof-dimensional state: runs times the average is chi-square with
// dof * runs degrees of freedom, so the band is
//   [chi2((1 - c) / 2, dof * runs), chi2((1 + c) / 2, dof * runs)] / runs.
// Throws std::invalid_argument unless dof >= 1, runs >= 1, 0 < confidence < 1.
NeesBand AverageNeesBand(int dof, int runs, double confidence = 0.95);

// The NEES of one filter along one drive, frame by frame: its mean against
// the band of an average over that many frames (AverageNeesBand, strict:
// successive frames are not independent), its median, and the share of
// frames inside the single frame's band.
struct NeesSummary {
  int frames = 0;
  double mean = 0.0;
  double median = 0.0;
  NeesBand mean_band;
  NeesBand frame_band;
  double share_inside_frame_band = 0.0;
};

// Throws std::invalid_argument under the conditions of AverageNeesBand; no
// frames give a summary of zeros.
NeesSummary SummarizeNees(std::vector<double> nees, int dof, double confidence = 0.95);

}  // namespace parkslam::eval

#endif  // PARKSLAM_EVAL_CONSISTENCY_H_
