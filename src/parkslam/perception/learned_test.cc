// The learned detector's C++ side: the networks OpenCV runs give the
// exported models' outputs, bad weights files fail clearly, slots are
// paired from points by the paper's rules, and the ID crop is cut upright.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "parkslam/perception/learned_slot_detector.h"
#include "parkslam/perception/learned_slot_id_reader.h"
#include "parkslam/perception/onnx_network.h"
#include "parkslam/perception/slot_pairing.h"

namespace parkslam::perception {
namespace {

using ::testing::HasSubstr;

const std::string kModelDir = PARKSLAM_MODEL_DIR;

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// The inputs of scripts/learned/reference_outputs.py, made by formula.
cv::Mat Pattern(int index, int channels, int height, int width) {
  const int shape[] = {1, channels, height, width};
  cv::Mat blob(4, shape, CV_32F);
  float* p = blob.ptr<float>();
  for (int c = 0; c < channels; ++c) {
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        *p++ = index == 0 ? static_cast<float>((37 * x + 91 * y + 53 * c) % 256)
                          : static_cast<float>(127.5 + 127.5 * std::sin(0.05 * x + 0.07 * y + c));
      }
    }
  }
  return blob;
}

// C++ inference through OpenCV's dnn module matches the exported model's
// output, evaluated from the ONNX file by PyTorch's operators, within 1e-4.
void ExpectMatchesReference(const std::string& name) {
  const std::string model = kModelDir + "/" + name + ".onnx";
  std::ifstream in(kModelDir + "/" + name + ".reference.json");
  ASSERT_TRUE(in.good()) << "missing " << name << ".reference.json";
  const nlohmann::json reference = nlohmann::json::parse(in);
  const std::vector<int> input = reference["input_shape"].get<std::vector<int>>();
  const std::vector<int> output = reference["outputs"][0]["shape"].get<std::vector<int>>();
  const OnnxNetwork network(model, input, output);
  for (const nlohmann::json& expected : reference["outputs"]) {
    const cv::Mat out = network.Forward(Pattern(expected["pattern"], input[1], input[2], input[3]));
    const std::vector<double> values = expected["values"].get<std::vector<double>>();
    ASSERT_EQ(out.total(), values.size());
    double worst = 0.0;
    for (size_t k = 0; k < values.size(); ++k) {
      worst = std::max(worst, std::abs(out.ptr<float>()[k] - values[k]));
    }
    EXPECT_LT(worst, 1e-4) << name << ", pattern " << expected["pattern"];
  }
}

TEST(LearnedModelsTest, MarkingPointNetworkMatchesTheExportedModel) {
  ExpectMatchesReference("marking_points");
}

TEST(LearnedModelsTest, SlotIdNetworkMatchesTheExportedModel) {
  ExpectMatchesReference("slot_ids");
}

TEST(LearnedModelsTest, BadWeightsFilesAreNamed) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("parkslam_learned_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  LearnedSlotDetectorOptions options;
  options.model_path = (dir / "absent.onnx").string();
  EXPECT_THAT(ErrorOf([&] { LearnedSlotDetector detector(options); }),
              HasSubstr("absent.onnx: no such weights file"));
  // Corrupt: a truncated copy of the real file, and plain text.
  const std::string real = kModelDir + "/marking_points.onnx";
  std::string bytes;
  {
    std::ifstream in(real, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  ASSERT_GT(bytes.size(), 1000u);
  std::ofstream(dir / "truncated.onnx", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  std::ofstream(dir / "text.onnx") << "not a network\n";
  for (const char* name : {"truncated.onnx", "text.onnx"}) {
    options.model_path = (dir / name).string();
    EXPECT_THAT(ErrorOf([&] { LearnedSlotDetector detector(options); }),
                HasSubstr(std::string(name) + ": not a network OpenCV's dnn module can read"));
  }
  // The ID reader's network where the marking-point network belongs.
  options.model_path = kModelDir + "/slot_ids.onnx";
  EXPECT_THAT(ErrorOf([&] { LearnedSlotDetector detector(options); }),
              HasSubstr("slot_ids.onnx: the network"));
  std::filesystem::remove_all(dir);
}

// Test-time flips average the cells of the mirrored views mirrored back,
// so the cells of a mirrored view are the mirrored cells of the view:
// index, offset and direction turned about the image's axis.
TEST(LearnedSlotDetectorTest, FlippedCellsAreMirrorConsistent) {
  LearnedSlotDetectorOptions options;
  options.model_path = kModelDir + "/marking_points.onnx";
  options.flips = 4;
  const LearnedSlotDetector detector(options);
  cv::Mat view(600, 600, CV_8UC3, cv::Scalar(90, 95, 100));
  // An asymmetric pair of T junctions, so that the mirror differs.
  cv::line(view, {100, 200}, {500, 200}, cv::Scalar(230, 230, 230), 8);
  cv::line(view, {150, 200}, {150, 480}, cv::Scalar(230, 230, 230), 8);
  cv::line(view, {420, 200}, {420, 480}, cv::Scalar(230, 230, 230), 8);
  cv::Mat mirrored;
  cv::flip(view, mirrored, 1);
  const cv::Mat a = detector.Cells(view), b = detector.Cells(mirrored);
  const int g = a.size[1];
  double worst = 0.0;
  for (int cy = 0; cy < g; ++cy) {
    for (int cx = 0; cx < g; ++cx) {
      const int mx = g - 1 - cx;
      const auto diff = [&](int k, float expected) {
        worst = std::max(worst, static_cast<double>(std::abs(b.at<float>(k, cy, mx) - expected)));
      };
      diff(0, a.at<float>(0, cy, cx));
      diff(1, 1.0f - a.at<float>(1, cy, cx));
      diff(2, a.at<float>(2, cy, cx));
      diff(3, -a.at<float>(3, cy, cx));
      diff(4, a.at<float>(4, cy, cx));
      diff(5, a.at<float>(5, cy, cx));
    }
  }
  // Resizing the mirrored view is the mirror of the resized view up to
  // rounding; the network's arithmetic adds no more than that.
  EXPECT_LT(worst, 2e-3);
  // Without flips the network alone is not mirror-symmetric.
  options.flips = 1;
  const LearnedSlotDetector plain(options);
  const cv::Mat pa = plain.Cells(view), pb = plain.Cells(mirrored);
  double plain_worst = 0.0;
  for (int cy = 0; cy < g; ++cy) {
    for (int cx = 0; cx < g; ++cx) {
      plain_worst = std::max(
          plain_worst,
          static_cast<double>(std::abs(pb.at<float>(0, cy, g - 1 - cx) - pa.at<float>(0, cy, cx))));
    }
  }
  EXPECT_GT(plain_worst, 10 * worst);
  options.flips = 3;
  EXPECT_THAT(ErrorOf([&] { LearnedSlotDetector bad(options); }),
              HasSubstr("flips: must be 1, 2 or 4"));
}

TEST(LearnedSlotDetectorTest, PointFiltersAreCheckedAndNamed) {
  LearnedSlotDetectorOptions options;
  options.model_path = "marking_points.onnx";
  std::string error;
  EXPECT_TRUE(options.IsValid(&error)) << error;
  EXPECT_DOUBLE_EQ(options.max_point_depth_towards_car_m, 4.0);
  EXPECT_DOUBLE_EQ(options.min_partner_confidence, 0.0);
  options.max_point_depth_towards_car_m = -1.0;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("max_point_depth_towards_car_m"));
  options.max_point_depth_towards_car_m = 0.0;  // off
  options.min_partner_confidence = options.min_confidence + 0.1;
  error.clear();
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("min_partner_confidence"));
  options.min_partner_confidence = 0.0;
  EXPECT_DOUBLE_EQ(options.weak_point_min_confidence, 0.0);
  options.weak_point_min_confidence = options.min_confidence + 0.1;
  error.clear();
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("weak_point_min_confidence"));
  options.weak_point_min_confidence = 0.5;
  options.weak_point_min_painted_share = 1.5;
  error.clear();
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("weak_point_min_painted_share"));
}

MarkingPoint Point(double x, double y, double direction_rad, double score = 0.9) {
  MarkingPoint p;
  p.px = {x, y};
  p.direction_rad = direction_rad;
  p.score = score;
  return p;
}

// A row of three T points on the right of the car (image centre 299.5),
// their separating lines running right (+x), 2.5 m apart at 60 px/m.
TEST(SlotPairingTest, PairsNeighboursOfARowOnly) {
  const std::vector<MarkingPoint> row{Point(400, 150, 0.0), Point(400, 300, 0.05),
                                      Point(400, 450, -0.05)};
  const std::vector<DetectedSlot> slots = PairMarkingPoints(row, {600, 600}, {});
  ASSERT_EQ(slots.size(), 2u);  // not the 5 m pair across the middle point
  for (const DetectedSlot& s : slots) {
    // Corner order: from corner 0 to corner 1 the slot lies on the right on
    // screen; corners 2 and 3 lie 5.3 m deeper.
    EXPECT_LT((s.corners_px[1] - s.corners_px[0]).x() * s.depth_dir_px.y() -
                  (s.corners_px[1] - s.corners_px[0]).y() * s.depth_dir_px.x(),
              0.0);
    EXPECT_NEAR((s.corners_px[2] - s.corners_px[1]).norm(), 5.3 * 60, 1e-6);
    EXPECT_NEAR(s.depth_dir_px.x(), 1.0, 0.01);
    EXPECT_NEAR(s.confidence, 0.9, 1e-9);
  }
}

TEST(SlotPairingTest, RejectsDisagreeingOrImplausiblePairs) {
  const SlotPairingOptions o;
  // Directions 40 degrees apart.
  EXPECT_TRUE(
      PairMarkingPoints({Point(400, 150, 0.0), Point(400, 300, 0.7)}, {600, 600}, o).empty());
  // Separating lines along the entrance.
  EXPECT_TRUE(
      PairMarkingPoints({Point(400, 150, M_PI / 2), Point(400, 300, M_PI / 2)}, {600, 600}, o)
          .empty());
  // Too short (1 m) and too long (8 m).
  EXPECT_TRUE(
      PairMarkingPoints({Point(400, 150, 0.0), Point(400, 210, 0.0)}, {600, 600}, o).empty());
  EXPECT_TRUE(
      PairMarkingPoints({Point(550, -100, 0.0), Point(550, 380, 0.0)}, {600, 600}, o).empty());
  // Opening away from the car (separating lines run left on the right),
  // the car 4.7 m past the entrance: beyond the row, where a back line's
  // junctions would pair.
  EXPECT_TRUE(
      PairMarkingPoints({Point(580, 150, M_PI), Point(580, 300, M_PI)}, {600, 600}, o).empty());
  // A parallel slot: 5 m long, 2.5 m deep.
  const std::vector<DetectedSlot> parallel =
      PairMarkingPoints({Point(400, 150, 0.0), Point(400, 450, 0.0)}, {600, 600}, o);
  ASSERT_EQ(parallel.size(), 1u);
  EXPECT_NEAR((parallel[0].corners_px[2] - parallel[0].corners_px[1]).norm(), 2.5 * 60, 1e-6);
}

// A row whose entrance runs 1.7 m right of the car, its separating lines
// running left, under the car: the car stands in the row, as when it parks,
// and the 2.5 m slot is kept; a 5 m (parallel) one is not, nor any without
// the exception.
TEST(SlotPairingTest, KeepsASlotOpeningTowardsTheCarOnlyWhenTheCarIsInItsRow) {
  SlotPairingOptions o;
  EXPECT_EQ(PairMarkingPoints({Point(400, 150, M_PI), Point(400, 300, M_PI)}, {600, 600}, o).size(),
            1u);
  EXPECT_TRUE(
      PairMarkingPoints({Point(400, 150, M_PI), Point(400, 450, M_PI)}, {600, 600}, o).empty());
  o.max_vehicle_depth_in_row_m = 0.0;
  EXPECT_TRUE(
      PairMarkingPoints({Point(400, 150, M_PI), Point(400, 300, M_PI)}, {600, 600}, o).empty());
  o.max_vehicle_depth_in_row_m = 1.5;  // the car 1.7 m in: beyond the allowed depth
  EXPECT_TRUE(
      PairMarkingPoints({Point(400, 150, M_PI), Point(400, 300, M_PI)}, {600, 600}, o).empty());
}

// The end line of a row at the image's left edge, its two ends 5.3 m apart
// with the row's entrance and back lines leaving the view after 0.5 m,
// pairs as a parallel slot; it is dropped, a parallel slot whose lines stay
// in view 1 m is kept, and so is a perpendicular slot at the edge.
TEST(SlotPairingTest, DropsParallelSlotsWhoseLinesLeaveTheView) {
  const SlotPairingOptions o;
  std::vector<DetectedSlot> slots =
      PairMarkingPoints({Point(30, 140, M_PI), Point(30, 458, M_PI)}, {600, 600}, o);
  ASSERT_EQ(slots.size(), 1u);
  DropParallelSlotsLeavingTheView({600, 600}, o, &slots);
  EXPECT_TRUE(slots.empty());

  slots = PairMarkingPoints({Point(60, 140, M_PI), Point(60, 458, M_PI)}, {600, 600}, o);
  DropParallelSlotsLeavingTheView({600, 600}, o, &slots);
  EXPECT_EQ(slots.size(), 1u);

  slots = PairMarkingPoints({Point(30, 150, M_PI), Point(30, 300, M_PI)}, {600, 600}, o);
  DropParallelSlotsLeavingTheView({600, 600}, o, &slots);
  EXPECT_EQ(slots.size(), 1u);

  SlotPairingOptions off = o;
  off.parallel_min_depth_in_view_m = 0.0;
  slots = PairMarkingPoints({Point(30, 140, M_PI), Point(30, 458, M_PI)}, {600, 600}, off);
  DropParallelSlotsLeavingTheView({600, 600}, off, &slots);
  EXPECT_EQ(slots.size(), 1u);
  off.parallel_min_depth_in_view_m = -1.0;
  std::string error;
  EXPECT_FALSE(off.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("parallel_min_depth_in_view_m"));
}
// A row on the right, 2.9 m slots (174 px); at the image's bottom edge the
// network puts a corner 2.2 m after the row's last one, where the border
// cuts the next junction. That slot is dropped; the same slot away from
// the border, and a slot of the row's width at the border, are kept.
TEST(SlotPairingTest, DropsAnOddlyWideSlotAtTheBorder) {
  const SlotPairingOptions o;
  const auto row = [&](double last_y) {
    return PairMarkingPoints(
        {Point(505, 100, 0.0), Point(505, 274, 0.0), Point(505, 448, 0.0), Point(505, last_y, 0.0)},
        {600, 600}, o);
  };
  std::vector<DetectedSlot> slots = row(580);
  ASSERT_EQ(slots.size(), 3u);
  DropOddSlotsAtTheBorder({600, 600}, o, &slots);
  ASSERT_EQ(slots.size(), 2u);
  for (const DetectedSlot& s : slots)
    EXPECT_LT(std::max(s.corners_px[0].y(), s.corners_px[1].y()), 500);

  slots = PairMarkingPoints({Point(505, 60, 0.0), Point(505, 234, 0.0), Point(505, 366, 0.0)},
                            {600, 600}, o);  // the odd one ends 234 px from the border
  ASSERT_EQ(slots.size(), 2u);
  DropOddSlotsAtTheBorder({600, 600}, o, &slots);
  EXPECT_EQ(slots.size(), 2u);

  slots = row(595);  // 147 px: 15.5 % narrower, at the border
  DropOddSlotsAtTheBorder({600, 600}, o, &slots);
  EXPECT_EQ(slots.size(), 2u);
  slots = row(599);  // 151 px: 13 % narrower, kept
  DropOddSlotsAtTheBorder({600, 600}, o, &slots);
  EXPECT_EQ(slots.size(), 3u);

  SlotPairingOptions off = o;
  off.border_width_check_m = 0.0;
  slots = row(580);
  DropOddSlotsAtTheBorder({600, 600}, off, &slots);
  EXPECT_EQ(slots.size(), 3u);
}

TEST(LearnedSlotIdReaderTest, CropsTheBoxUpright) {
  // A white bar across the top half of a box whose reader's "right" points
  // down the image: upright in the crop, the bar lies on the crop's top.
  cv::Mat view(600, 600, CV_8UC3, cv::Scalar(60, 60, 60));
  TextBox box;
  box.centre_px = {300, 300};
  box.right_dir = {0, 1};
  box.text_height_px = 20;  // the crop: 32 x 96 px
  // The box's top is the reader's up: right (0, 1) turned anticlockwise on
  // screen is (1, 0), so the top lies at larger x.
  cv::rectangle(view, cv::Point(302, 260), cv::Point(315, 340), cv::Scalar(255, 255, 255),
                cv::FILLED);
  const cv::Mat crop = LearnedSlotIdReader::Crop(view, box);
  ASSERT_EQ(crop.size(), cv::Size(96, 32));
  cv::Mat grey;
  cv::cvtColor(crop, grey, cv::COLOR_BGR2GRAY);
  EXPECT_GT(cv::mean(grey.rowRange(4, 12))[0], 200.0);
  EXPECT_LT(cv::mean(grey.rowRange(20, 32))[0], 80.0);
}

TEST(LearnedSlotIdReaderTest, ReadsNothingOutsideTheView) {
  LearnedSlotIdReaderOptions options;
  options.model_path = kModelDir + "/slot_ids.onnx";
  const LearnedSlotIdReader reader(options);
  const cv::Mat view(600, 600, CV_8UC3, cv::Scalar(90, 90, 90));
  TextBox box;
  box.centre_px = {595, 300};
  EXPECT_TRUE(reader.ReadBox(view, box).empty());
  const cv::Mat unseen(600, 600, CV_8UC3, cv::Scalar(0, 0, 0));
  box.centre_px = {300, 300};
  EXPECT_TRUE(reader.ReadBox(unseen, box).empty());
}

// The network's output with, at each position, "no character" or one
// character at the given probabilities (the rest spread evenly).
cv::Mat Output(const std::vector<std::pair<char, float>>& positions) {
  cv::Mat p(kIdPositions, kIdClasses, CV_32F);
  for (int k = 0; k < kIdPositions; ++k) {
    const auto [c, probability] = k < static_cast<int>(positions.size())
                                      ? positions[static_cast<std::size_t>(k)]
                                      : std::pair<char, float>{' ', 1.0f};
    const int cls = c == ' ' ? 0 : 1 + static_cast<int>(std::string(kIdAlphabet).find(c));
    p.row(k).setTo((1.0f - probability) / static_cast<float>(kIdClasses - 1));
    p.at<float>(k, cls) = probability;
  }
  return p;
}

TEST(LearnedSlotIdReaderTest, DecodeReadsUntilAPositionIsSurelyEmpty) {
  const LearnedSlotIdReaderOptions options;  // both thresholds 0.8
  EXPECT_DOUBLE_EQ(options.min_digit_probability, 0.8);
  EXPECT_DOUBLE_EQ(options.min_end_probability, 0.8);
  EXPECT_EQ(LearnedSlotIdReader::Decode(Output({{'1', 0.99f}, {'4', 0.95f}}), options).best(),
            "14");
  EXPECT_EQ(
      LearnedSlotIdReader::Decode(Output({{'A', 0.9f}, {'7', 0.9f}, {' ', 0.9f}}), options).best(),
      "A7");
  // A character too unsure is unread; so is a position that is more likely
  // empty than not, but not surely: a worn last digit gives "1?", not "1".
  EXPECT_EQ(LearnedSlotIdReader::Decode(Output({{'1', 0.99f}, {'4', 0.6f}}), options).best(), "1?");
  EXPECT_EQ(LearnedSlotIdReader::Decode(Output({{'1', 0.99f}, {' ', 0.7f}}), options).best(), "1?");
  LearnedSlotIdReaderOptions loose;
  loose.min_digit_probability = 0.5;
  loose.min_end_probability = 0.5;
  EXPECT_EQ(LearnedSlotIdReader::Decode(Output({{'1', 0.99f}, {' ', 0.45f}}), loose).best(), "1?");
  EXPECT_EQ(LearnedSlotIdReader::Decode(Output({{'1', 0.99f}, {' ', 0.7f}}), loose).best(), "1");
  EXPECT_EQ(LearnedSlotIdReader::Decode(Output({{'1', 0.99f}, {'4', 0.6f}}), loose).best(), "14");
  // Nothing read at all: empty.
  EXPECT_TRUE(LearnedSlotIdReader::Decode(Output({{' ', 0.45f}}), options).empty());
  EXPECT_TRUE(LearnedSlotIdReader::Decode(Output({}), options).empty());
  EXPECT_THROW(LearnedSlotIdReader::Decode(cv::Mat(2, 3, CV_32F, cv::Scalar(0)), options),
               std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::perception
