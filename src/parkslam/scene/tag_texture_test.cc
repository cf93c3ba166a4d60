#include "parkslam/scene/tag_texture.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <stdexcept>

namespace parkslam::scene {
namespace {

TEST(TagTextureTest, IsTenCellsWithWhiteOuterRingAndBlackBorder) {
  const cv::Mat tag = Tag36h11Image(7, 4);
  ASSERT_EQ(tag.type(), CV_8UC1);
  EXPECT_EQ(tag.cols, kTagTotalCells * 4);
  EXPECT_EQ(tag.rows, kTagTotalCells * 4);
  EXPECT_EQ(tag.at<std::uint8_t>(0, 0), 255);              // white outer cell
  EXPECT_EQ(tag.at<std::uint8_t>(4, 4), 0);                // black border cell
  EXPECT_EQ(tag.at<std::uint8_t>(4 * 9 + 2, 4 * 5), 255);  // bottom white ring
}

TEST(TagTextureTest, LibapriltagDecodesItsIdAndCornersStartBottomLeft) {
  constexpr int kPixelsPerCell = 12, kPad = 30;
  apriltag_family_t* family = tag36h11_create();
  apriltag_detector_t* detector = apriltag_detector_create();
  apriltag_detector_add_family(detector, family);
  detector->nthreads = 1;
  for (int id : {0, 5, 41, 586}) {
    const cv::Mat tag = Tag36h11Image(id, kPixelsPerCell);
    cv::Mat page(tag.rows + 2 * kPad, tag.cols + 2 * kPad, CV_8UC1, cv::Scalar(255));
    tag.copyTo(page(cv::Rect(kPad, kPad, tag.cols, tag.rows)));
    image_u8_t image{page.cols, page.rows, static_cast<int32_t>(page.step[0]), page.data};
    zarray_t* detections = apriltag_detector_detect(detector, &image);
    ASSERT_EQ(zarray_size(detections), 1) << "tag " << id;
    apriltag_detection_t* det = nullptr;
    zarray_get(detections, 0, &det);
    EXPECT_EQ(det->id, id);
    // The black square spans cells 1..8, its edges between pixels kPad + 11
    // and kPad + 12 and between kPad + 107 and kPad + 108. libapriltag puts
    // pixel centres at half-integers, so the edges read as whole numbers
    // there (0.5 more than in the camera models' convention).
    const double lo = kPad + kPixelsPerCell, hi = kPad + 9 * kPixelsPerCell;
    EXPECT_NEAR(det->p[0][0], lo, 0.3);  // bottom-left
    EXPECT_NEAR(det->p[0][1], hi, 0.3);
    EXPECT_NEAR(det->p[1][0], hi, 0.3);  // bottom-right
    EXPECT_NEAR(det->p[1][1], hi, 0.3);
    EXPECT_NEAR(det->p[2][0], hi, 0.3);  // top-right
    EXPECT_NEAR(det->p[2][1], lo, 0.3);
    EXPECT_NEAR(det->p[3][0], lo, 0.3);  // top-left
    EXPECT_NEAR(det->p[3][1], lo, 0.3);
    apriltag_detections_destroy(detections);
  }
  apriltag_detector_destroy(detector);
  tag36h11_destroy(family);
}

TEST(TagTextureTest, RejectsIdsOutsideTheFamily) {
  EXPECT_EQ(Tag36h11Count(), 587);
  EXPECT_THROW(Tag36h11Image(-1), std::out_of_range);
  EXPECT_THROW(Tag36h11Image(587), std::out_of_range);
  EXPECT_THROW(Tag36h11Image(3, 0), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::scene
