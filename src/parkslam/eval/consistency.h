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

// The integrated autocorrelation time of a series, in samples: 1 + 2 times
// the sum of its autocorrelations up to the lag M, the smallest with
// M >= 5 times the estimate so far (Sokal's automatic window; Sokal, "Monte
// Carlo Methods in Statistical Mechanics", 1997, section 3). A white series
// gives about 1; n / time is how many independent samples its mean is
// worth. At least 1; 1 for fewer than two samples or a constant series.
double IntegratedAutocorrelationTime(const std::vector<double>& series);

// The NEES of one filter along one drive, frame by frame: its mean against
// the band of an average over that many frames (AverageNeesBand), and
// against the band of an average over the independent frames they are
// worth (effective_frames: frames over IntegratedAutocorrelationTime, for
// one frame's error lives on in the next ones: the strict band treats a
// 10 Hz drive of 6,000 correlated frames as 6,000 independent runs); its
// median, and the share of frames inside the single frame's band.
struct NeesSummary {
  int frames = 0;
  double mean = 0.0;
  double median = 0.0;
  NeesBand mean_band;
  int effective_frames = 0;
  NeesBand effective_mean_band;
  NeesBand frame_band;
  double share_inside_frame_band = 0.0;
};

// Throws std::invalid_argument under the conditions of AverageNeesBand; no
// frames give a summary of zeros.
NeesSummary SummarizeNees(std::vector<double> nees, int dof, double confidence = 0.95);

}  // namespace parkslam::eval

#endif  // PARKSLAM_EVAL_CONSISTENCY_H_
