#ifndef PARKSLAM_SCENE_TAG_TEXTURE_H_
#define PARKSLAM_SCENE_TAG_TEXTURE_H_

// AprilTag images for the renderer (paper III-B: tag36h11 on pillars and
// walls), drawn by libapriltag itself so that its detector decodes them.

#include <opencv2/core.hpp>

namespace parkslam::scene {

// tag36h11 as libapriltag draws it (apriltag_to_image): kTagTotalCells
// cells square, a one-cell white border around the black square of
// kTagBlackCells cells, which frames the 6 x 6 data bits. The tag's size in
// the world (sim::WorldTag::size_m) is the edge of the black square.
inline constexpr int kTagTotalCells = 10;
inline constexpr int kTagBlackCells = 8;

// Number of tags in the tag36h11 family (valid IDs are 0 .. count - 1).
int Tag36h11Count();

// The image of tag `tag_id`, CV_8UC1, 0 black and 255 white, each cell a
// square of pixels_per_cell pixels. Orientation is libapriltag's: shown
// upright (row 0 at the top) the detector reports its corners p[0..3] as
// bottom-left, bottom-right, top-right, top-left, which are the tag-frame
// points (-s/2, s/2), (s/2, s/2), (s/2, -s/2), (-s/2, -s/2) of
// solvePnP(SOLVEPNP_IPPE_SQUARE) with x right and y down on the tag.
// Throws std::out_of_range for an ID outside the family and
// std::invalid_argument for pixels_per_cell < 1.
cv::Mat Tag36h11Image(int tag_id, int pixels_per_cell = 1);

}  // namespace parkslam::scene

#endif  // PARKSLAM_SCENE_TAG_TEXTURE_H_
