#ifndef PARKSLAM_IO_HOMOGRAPHY_RIG_H_
#define PARKSLAM_IO_HOMOGRAPHY_RIG_H_

#include <filesystem>

#include "parkslam/camera/homography_top_view.h"

namespace parkslam::io {

// Reads a rig calibrated by ground homographies: front.yaml, back.yaml,
// left.yaml and right.yaml in `folder` (OpenCV FileStorage: camera_matrix,
// dist_coeffs (cv::fisheye), resolution, project_matrix, scale_xy,
// shift_xy), as in shared/data/surround-view-sample. Throws IoError naming
// the file, the line and the field. Parsed as YAML (not by OpenCV).
camera::HomographyRig LoadHomographyRig(const std::filesystem::path& folder);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_HOMOGRAPHY_RIG_H_
