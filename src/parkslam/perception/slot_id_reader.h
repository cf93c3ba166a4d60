#ifndef PARKSLAM_PERCEPTION_SLOT_ID_READER_H_
#define PARKSLAM_PERCEPTION_SLOT_ID_READER_H_

// Slot-ID reading in the top view (paper III-A: "the slot ID is recognized
// digit by digit, with confidence"):
//  1. rectification: the region where the ID may stand, from the entrance
//     line, warped so that the digits stand upright at one pixel per
//     top-view pixel;
//  2. floor and paint levels from the region's histogram; no paint, no
//     reading;
//  3. layout: the band of the digits' height holding the most ink, then the
//     number of digits and their place along it that best explain the ink
//     (the font's geometry: font/digit_font.h), within max_offset_m of
//     where the entrance puts them; a layout that a longer ID partly out of
//     sight would explain as well, or one leaving much paint unexplained,
//     gives no reading;
//  4. worn paint: an ID much fainter than the slot's own lines is not read;
//  5. each digit cell rectified to the classifier's patch and classified
//     (digit_classifier.h): 10 digits and "not a digit", with softmax
//     probabilities.
//
// Top-view pixels are 0-based, (0, 0) the centre of the top-left pixel,
// x to the right and y down (camera/top_view.h); 0 marks pixels no camera
// saw (the car's footprint).

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "parkslam/perception/digit_classifier.h"
#include "parkslam/sensor/sensor_data.h"

namespace parkslam::perception {

struct SlotIdReaderOptions {
  double pixels_per_m = 60.0;  // top-view scale (600 px for 10 m)
  // Where the painted ID sits (render/ground_raster.h): its foot
  // id_setback_m inside the entrance, id_height_m tall, centred on the
  // entrance's midpoint along the slot's depth direction.
  double id_setback_m = 0.3;
  double id_height_m = 0.6;
  int max_digits = 3;
  // Hypotheses below this probability are dropped from a digit's reading; a
  // digit whose best class falls below min_digit_probability is unread.
  double min_hypothesis_probability = 0.05;
  double min_digit_probability = 0.5;
  // How far the painted digits may lie from where the entrance puts them,
  // along both axes (the entrance's corners carry detection error).
  double max_offset_m = 0.15;
  // Worn paint (render/ground_raster.h: 40 % opacity, flaked) is told by
  // its brightness next to the slot's own separating lines, painted with
  // the same paint: an ID whose paint contrast is below this share of the
  // lines' is not read. 0 turns the check off.
  double min_paint_ratio = 0.55;

  bool IsValid(std::string* error) const;

  // The field list, walked by the options file reader (io/options_yaml.h).
  template <typename V>
  void VisitFields(V& v) {
    v("pixels_per_m", pixels_per_m);
    v("id_setback_m", id_setback_m);
    v("id_height_m", id_height_m);
    v("max_digits", max_digits);
    v("min_hypothesis_probability", min_hypothesis_probability);
    v("min_digit_probability", min_digit_probability);
    v("max_offset_m", max_offset_m);
    v("min_paint_ratio", min_paint_ratio);
  }
};

// The geometry of one slot's entrance in the top view.
struct EntranceInImage {
  Eigen::Vector2d corner0_px = Eigen::Vector2d::Zero();  // slot corner 0
  Eigen::Vector2d corner1_px = Eigen::Vector2d::Zero();  // slot corner 1
  // Unit vector from the entrance into the slot, along its separating
  // lines (the direction the digits' "up" points).
  Eigen::Vector2d depth_dir_px = Eigen::Vector2d::UnitY();
};

// Why a reading came out as it did, for tests and diagnostics.
struct SlotIdReadDetails {
  // "read", "partial", or why nothing was read: "bad entrance", "region
  // not seen", "no paint", "no digits", "stray paint", "maybe longer",
  // "not seen", "worn", "unread" (no digit classified confidently).
  std::string outcome;
  int digits_found = 0;  // digit cells of the layout found
  // Where the layout found the digits, from where the entrance puts them:
  // along the reading direction and into the slot, top-view pixels.
  Eigen::Vector2d offset_px = Eigen::Vector2d::Zero();
  // Ink in the band that no digit cell of the layout holds, as a share of
  // the ink its cells hold.
  double stray_ink = 0.0;
  double contrast_grey = 0.0;          // paint over floor in the ID's region
  double noise_grey = 0.0;             // the floor's noise there
  double paint_ratio = -1.0;           // the ID's paint contrast over its lines'; -1: no line seen
  std::vector<cv::Mat> digit_patches;  // the classifier's inputs, one per digit cell
};

class SlotIdReader {
 public:
  // Trains the digit classifier on first use in the process (about 0.4 s,
  // deterministic: digit_classifier.h). Throws std::invalid_argument on
  // invalid options.
  explicit SlotIdReader(const SlotIdReaderOptions& options = {});

  // Reads the ID painted inside one slot of an 8-bit grey top view: one
  // DigitReading per digit, its hypotheses of at least
  // min_hypothesis_probability sorted by falling probability, none when its
  // best digit falls below min_digit_probability. Returns an empty reading
  // when no digit is read (nothing painted, worn, the region leaving the
  // image or under the car), a partial one when some digits are unread.
  // Throws std::invalid_argument for an image that is not 8-bit grey.
  SlotIdReading Read(const cv::Mat& top_view_grey, const EntranceInImage& entrance) const;
  // The same, saying why in *details (may be null).
  SlotIdReading Read(const cv::Mat& top_view_grey, const EntranceInImage& entrance,
                     SlotIdReadDetails* details) const;

  const SlotIdReaderOptions& options() const { return options_; }

 private:
  SlotIdReaderOptions options_;
  const DigitClassifier* classifier_ = nullptr;
};

}  // namespace parkslam::perception

#endif  // PARKSLAM_PERCEPTION_SLOT_ID_READER_H_
