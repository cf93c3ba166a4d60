#ifndef PARKSLAM_PERCEPTION_LEARNED_SLOT_ID_READER_H_
#define PARKSLAM_PERCEPTION_LEARNED_SLOT_ID_READER_H_

// Learned slot-ID reading (paper III-A: "the slot ID is recognized digit by
// digit, with confidence"; the paper uses PVANet): the box where the ID is
// painted is cut from the top view, upright for a reader, as a 96 x 32 crop
// (as `parkslam make-training-set --kind ids` writes them), and a small
// network (scripts/learned/models.py, SlotIdNet) gives, for each of four
// character positions, probabilities over "no character" and the alphabet
// (digits, capital letters, '-'). Characters are read from the left until
// the first position whose best class is "no character"; each becomes a
// DigitReading with its hypotheses, so that the mapper's digit-by-digit
// hypotheses and partial IDs work as with the classical reader.
//
// Where the ID stands: Read() uses the default lot's convention (as the
// classical reader: the ID's foot id_setback_m inside the entrance, centred
// on it, upright for a reader in the aisle); ReadBox() reads any box.

#include <memory>
#include <string>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "parkslam/perception/onnx_network.h"
#include "parkslam/perception/slot_id_reader.h"
#include "parkslam/sensor/sensor_data.h"

namespace parkslam::perception {

// The characters a slot ID may hold, in the network's class order (class 0
// is "no character").
inline constexpr char kIdAlphabet[] = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ-";
inline constexpr int kIdPositions = 4;
// Classes per position: "no character" and the alphabet (sizeof counts
// its terminating NUL).
inline constexpr int kIdClasses = 1 + static_cast<int>(sizeof(kIdAlphabet) - 1);

struct LearnedSlotIdReaderOptions {
  std::string model_path;  // models/slot_ids.onnx in the source tree
  double pixels_per_m = 60.0;
  double id_setback_m = 0.3;
  double id_height_m = 0.6;
  // Hypotheses below this probability are dropped from a character's
  // reading; a character whose best class falls below
  // min_digit_probability is unread. The ID ends only at a position whose
  // "no character" reaches min_end_probability; a position less sure than
  // that is an unread character.
  // At 0.8 (0.5 before), a worn ID is read in part rather than wrong: on
  // the default lot's drives the network read 10 and 13 worn IDs whole and
  // wrong, then 2 and 3, and the demo map names no slot wrong (it had two);
  // readable IDs stay 100 % right (docs/learned_perception.md).
  double min_hypothesis_probability = 0.05;
  double min_digit_probability = 0.8;
  double min_end_probability = 0.8;

  bool IsValid(std::string* error) const;

  // The field list, walked by the options file reader (io/options_yaml.h).
  template <typename V>
  void VisitFields(V& v) {
    v("model_path", model_path);
    v("pixels_per_m", pixels_per_m);
    v("id_setback_m", id_setback_m);
    v("id_height_m", id_height_m);
    v("min_hypothesis_probability", min_hypothesis_probability);
    v("min_digit_probability", min_digit_probability);
    v("min_end_probability", min_end_probability);
  }
};

// Where painted text stands in the top view: its centre, the direction a
// reader's "right" points along the text, and the characters' height,
// top-view pixels.
struct TextBox {
  Eigen::Vector2d centre_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d right_dir = Eigen::Vector2d::UnitX();
  double text_height_px = 36.0;
};

class LearnedSlotIdReader {
 public:
  // Loads the network. Throws std::invalid_argument on invalid options and
  // std::runtime_error naming the file when the weights are missing or
  // unusable.
  explicit LearnedSlotIdReader(const LearnedSlotIdReaderOptions& options);

  // Reads the ID of one slot of an 8-bit BGR (or grey) top view, where the
  // default lot paints it. Empty when nothing is read, or when the box
  // leaves the image or covers pixels no camera saw (0 in a grey view, pure
  // black in a colour one).
  SlotIdReading Read(const cv::Mat& top_view, const EntranceInImage& entrance) const;
  // Reads the text in `box`.
  SlotIdReading ReadBox(const cv::Mat& top_view, const TextBox& box) const;

  // The network's input for `box`: the crop, 96 x 32, upright, its height
  // 1.6 times the text's and its width three times that (scene/labels.cc
  // cuts the training crops the same way); as many channels as the view.
  static cv::Mat Crop(const cv::Mat& top_view, const TextBox& box);
  // The network's output for a crop (grey or BGR): kIdPositions x
  // (1 + alphabet) floats.
  cv::Mat Probabilities(const cv::Mat& crop) const;
  // The reading of the network's output `p` (kIdPositions x (1 +
  // alphabet), CV_32F): characters from the left until a position is surely
  // empty ("no character" at least min_end_probability); a position
  // unsure whether it holds a character, or which, is an unread character.
  static SlotIdReading Decode(const cv::Mat& p, const LearnedSlotIdReaderOptions& options);

  const LearnedSlotIdReaderOptions& options() const { return options_; }

 private:
  LearnedSlotIdReaderOptions options_;
  std::unique_ptr<OnnxNetwork> network_;
};

}  // namespace parkslam::perception

#endif  // PARKSLAM_PERCEPTION_LEARNED_SLOT_ID_READER_H_
