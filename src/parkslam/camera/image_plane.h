#ifndef PARKSLAM_CAMERA_IMAGE_PLANE_H_
#define PARKSLAM_CAMERA_IMAGE_PLANE_H_

// The sensor stream's grey images (sensor/sensor_data.h, ImagePlane) and
// OpenCV's, both ways.

#include <opencv2/core.hpp>

#include "parkslam/sensor/sensor_data.h"

namespace parkslam::camera {

// A copy of an 8-bit grey image, without padding. Throws
// std::invalid_argument for any other type.
ImagePlane ToImagePlane(const cv::Mat& grey);

// A cv::Mat header over the plane's shared pixels (no copy): valid while
// the plane lives; not to be written to.
cv::Mat AsMat(const ImagePlane& plane);

}  // namespace parkslam::camera

#endif  // PARKSLAM_CAMERA_IMAGE_PLANE_H_
