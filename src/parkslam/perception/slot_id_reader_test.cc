#include "parkslam/perception/slot_id_reader.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iostream>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "parkslam/camera/top_view.h"
#include "parkslam/common/random.h"
#include "parkslam/common/se2.h"
#include "parkslam/font/digit_font.h"
#include "parkslam/render/ground_raster.h"
#include "parkslam/render/renderer.h"
#include "parkslam/sim/route.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/world.h"

namespace parkslam::perception {
namespace {

constexpr double kPixelsPerM = 60.0;
constexpr int kTopViewPx = 600;
constexpr double kCenterPx = (kTopViewPx - 1) / 2.0;

// ---------------------------------------------------------------------------
// A synthetic lot: rows of perpendicular, 60-degree angled and parallel
// slots, every digit in every position of 2- and 3-digit IDs, painted by the
// simulator's own ground raster.

std::vector<std::string> TwoDigitIds() {
  std::vector<std::string> ids;
  for (int k = 0; k < 10; ++k)
    ids.push_back({static_cast<char>('0' + k), static_cast<char>('0' + (7 * k + 3) % 10)});
  for (const char* id : {"11", "88", "38", "07"}) ids.push_back(id);
  return ids;
}

std::vector<std::string> ThreeDigitIds() {
  std::vector<std::string> ids;
  for (int k = 0; k < 10; ++k) {
    ids.push_back({static_cast<char>('0' + k), static_cast<char>('0' + (3 * k + 5) % 10),
                   static_cast<char>('0' + (9 * k + 1) % 10)});
  }
  for (const char* id : {"214", "111", "888", "101"}) ids.push_back(id);
  return ids;
}

sim::WorldSlot MakeSlot(const Eigen::Vector2d& c0, const Eigen::Vector2d& along,
                        const Eigen::Vector2d& into, double entrance_m, double depth_m,
                        const std::string& id, bool legible) {
  sim::WorldSlot slot;
  slot.corners_map = {c0, c0 + along * entrance_m, c0 + along * entrance_m + into * depth_m,
                      c0 + into * depth_m};
  slot.painted_id = id;
  slot.id_legible = legible;
  return slot;
}

sim::World MakeLot(bool legible) {
  sim::World world;
  const Eigen::Vector2d east = Eigen::Vector2d::UnitX(), north = Eigen::Vector2d::UnitY();
  std::vector<std::string> ids = TwoDigitIds();
  for (const std::string& id : ThreeDigitIds()) ids.push_back(id);
  for (size_t k = 0; k < ids.size(); ++k) {
    world.slots.push_back(
        MakeSlot({2.5 * static_cast<double>(k), 0.0}, east, north, 2.5, 5.3, ids[k], legible));
  }
  // 60-degree angled slots (2.5 m between separating lines).
  const double angle = std::numbers::pi / 3;
  const Eigen::Vector2d slanted(std::cos(angle), std::sin(angle));
  const double angled_entrance_m = 2.5 / std::sin(angle);
  const std::vector<std::string> angled = {"70", "81", "92", "03", "14",
                                           "25", "36", "47", "58", "69"};
  for (size_t k = 0; k < angled.size(); ++k) {
    world.slots.push_back(MakeSlot({angled_entrance_m * static_cast<double>(k), -16.0}, east,
                                   slanted, angled_entrance_m, 5.3, angled[k], legible));
  }
  // Parallel slots.
  const std::vector<std::string> parallel = {"201", "352", "463", "574", "685", "796"};
  for (size_t k = 0; k < parallel.size(); ++k) {
    world.slots.push_back(MakeSlot({6.0 * static_cast<double>(k), -30.0}, east, north, 6.0, 2.5,
                                   parallel[k], legible));
  }
  // Slots without an ID.
  for (int k = 0; k < 3; ++k) {
    world.slots.push_back(MakeSlot({40.0 + 2.5 * k, -30.0}, east, north, 2.5, 5.3, "", legible));
  }
  world.hall = {-2.0, -32.0, 72.0, 7.0};
  return world;
}

const render::GroundRaster& LotRaster(bool legible) {
  static const render::GroundRaster legible_raster(MakeLot(true), render::GroundRasterOptions{},
                                                   11);
  static const render::GroundRaster worn_raster(MakeLot(false), render::GroundRasterOptions{}, 11);
  return legible ? legible_raster : worn_raster;
}

const std::vector<sim::WorldSlot>& LotSlots() {
  static const sim::World world = MakeLot(true);
  return world.slots;
}

const SlotIdReader& DefaultReader() {
  static const SlotIdReader reader;
  return reader;
}

// How the top view degrades the floor: blur, noise, lower contrast.
struct Degradation {
  double blur_px = 0.7;
  double noise_grey = 2.0;
  double contrast = 1.0;  // paint and floor contrast kept
};

// Error of the entrance's corners (each, per axis) and direction.
struct EntranceError {
  double corner_sigma_px = 0.0;
  double direction_sigma_rad = 0.0;
};

struct View {
  cv::Mat image;
  EntranceInImage entrance;
  SE2 T_map_vehicle;
};

// The slot's ID seen in a top view (as camera/top_view.h: the car points
// up, x right is the vehicle's -y) from a car standing in the aisle, turned
// so that the slot's depth direction shows as `screen_dir` on screen. The ID
// stands `distance_m` ahead of the view's centre along its depth direction.
View MakeView(const sim::WorldSlot& slot, bool legible, const Eigen::Vector2d& screen_dir,
              double distance_m, const Degradation& degradation, const EntranceError& error,
              std::uint64_t seed) {
  const auto& c = slot.corners_map;
  const Eigen::Vector2d mid = (c[0] + c[1]) / 2;
  const Eigen::Vector2d up_map = ((c[2] + c[3]) / 2 - mid).normalized();
  // screen (x, y) = (-v.y, -v.x) for a vehicle-frame vector v.
  const Eigen::Vector2d up_vehicle(-screen_dir.y(), -screen_dir.x());
  const double yaw =
      std::atan2(up_map.y(), up_map.x()) - std::atan2(up_vehicle.y(), up_vehicle.x());
  const Eigen::Vector2d id_center = mid + up_map * 0.6;
  const SE2 T_map_vehicle(id_center - up_map * distance_m, yaw);

  const render::GroundRaster& raster = LotRaster(legible);
  const auto map_of_pixel = [&](double u, double v) {
    return T_map_vehicle *
           Eigen::Vector2d((kCenterPx - v) / kPixelsPerM, (kCenterPx - u) / kPixelsPerM);
  };
  const Eigen::Vector2d o = raster.PixelOf(map_of_pixel(0, 0));
  const Eigen::Vector2d du = raster.PixelOf(map_of_pixel(1, 0)) - o;
  const Eigen::Vector2d dv = raster.PixelOf(map_of_pixel(0, 1)) - o;
  const cv::Matx23d top_to_raster(du.x(), dv.x(), o.x(), du.y(), dv.y(), o.y());
  cv::Mat top;
  cv::warpAffine(raster.image(), top, top_to_raster, cv::Size(kTopViewPx, kTopViewPx),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP);
  cv::Mat grey;
  top.convertTo(grey, CV_32F);
  if (degradation.blur_px > 0.0) cv::GaussianBlur(grey, grey, cv::Size(0, 0), degradation.blur_px);
  const double mean = cv::mean(grey)[0];
  grey = (grey - mean) * degradation.contrast + mean;
  cv::Mat noise(grey.size(), CV_32F);
  cv::RNG(seed).fill(noise, cv::RNG::NORMAL, 0.0, degradation.noise_grey);
  grey += noise;
  View view;
  grey.convertTo(view.image, CV_8U);
  view.image = cv::max(view.image, 1);  // 0 means "no camera saw it"
  view.T_map_vehicle = T_map_vehicle;

  const auto pixel_of_map = [&](const Eigen::Vector2d& p_map) {
    const Eigen::Vector2d v = T_map_vehicle.inverse() * p_map;
    return Eigen::Vector2d(kCenterPx - v.y() * kPixelsPerM, kCenterPx - v.x() * kPixelsPerM);
  };
  Random rng(seed);
  view.entrance.corner0_px =
      pixel_of_map(c[0]) +
      Eigen::Vector2d(rng.Gaussian(error.corner_sigma_px), rng.Gaussian(error.corner_sigma_px));
  view.entrance.corner1_px =
      pixel_of_map(c[1]) +
      Eigen::Vector2d(rng.Gaussian(error.corner_sigma_px), rng.Gaussian(error.corner_sigma_px));
  const double turn = rng.Gaussian(error.direction_sigma_rad);
  const Eigen::Rotation2Dd rotation(turn);
  view.entrance.depth_dir_px = rotation * screen_dir.normalized();
  return view;
}

const std::vector<Eigen::Vector2d>& ScreenDirections() {
  // Depth direction up, down, left, right on screen, and two slanted ones.
  static const std::vector<Eigen::Vector2d> directions = {{0, -1},
                                                          {0, 1},
                                                          {-1, 0},
                                                          {1, 0},
                                                          Eigen::Vector2d(1, -2).normalized(),
                                                          Eigen::Vector2d(-3, 1).normalized()};
  return directions;
}

struct Tally {
  int ids = 0, right = 0, wrong = 0, partial = 0, empty = 0;
  double confidence_right = 0.0, confidence_wrong = 0.0;
  int confident = 0, confident_right = 0;  // confidence >= 0.8

  double accuracy() const { return static_cast<double>(right) / ids; }
  void Add(const SlotIdReading& reading, const std::string& truth) {
    ++ids;
    if (reading.empty()) {
      ++empty;
    } else if (reading.partial()) {
      ++partial;
    } else if (reading.best() == truth) {
      ++right;
      confidence_right += reading.confidence();
    } else {
      ++wrong;
      confidence_wrong += reading.confidence();
    }
    if (!reading.empty() && !reading.partial() && reading.confidence() >= 0.8) {
      ++confident;
      confident_right += reading.best() == truth;
    }
  }
};

std::string Describe(const Tally& t) {
  return std::to_string(t.right) + " right, " + std::to_string(t.wrong) + " wrong, " +
         std::to_string(t.partial) + " partial, " + std::to_string(t.empty) + " empty of " +
         std::to_string(t.ids) + "; " + std::to_string(t.confident_right) + " of " +
         std::to_string(t.confident) + " confident (>= 0.8) full readings right";
}

// Reads every painted slot of the lot in every screen direction.
Tally ReadLot(const SlotIdReader& reader, bool legible, const Degradation& degradation,
              const EntranceError& error, double distance_m = 1.8) {
  Tally tally;
  std::uint64_t seed = 1;
  for (const sim::WorldSlot& slot : LotSlots()) {
    if (slot.painted_id.empty()) continue;
    for (const Eigen::Vector2d& dir : ScreenDirections()) {
      const View view = MakeView(slot, legible, dir, distance_m, degradation, error, ++seed);
      tally.Add(reader.Read(view.image, view.entrance), slot.painted_id);
    }
  }
  return tally;
}

const sim::WorldSlot& SlotWithId(const std::string& id) {
  for (const sim::WorldSlot& slot : LotSlots()) {
    if (slot.painted_id == id) return slot;
  }
  throw std::invalid_argument("no slot " + id);
}

// ---------------------------------------------------------------------------

TEST(SlotIdReaderTest, ReadsCleanIdsInEveryOrientation) {
  const Tally t = ReadLot(DefaultReader(), true, Degradation{}, EntranceError{});
  RecordProperty("clean", Describe(t));
  EXPECT_EQ(t.ids, (14 + 14 + 10 + 6) * 6);
  EXPECT_GE(t.accuracy(), 0.98) << Describe(t);
  EXPECT_EQ(t.wrong, 0) << Describe(t);
}

TEST(SlotIdReaderTest, ReadsBlurredNoisyFadedIds) {
  Degradation far;
  far.blur_px = 1.8;
  far.noise_grey = 6.0;
  far.contrast = 0.7;
  const Tally t = ReadLot(DefaultReader(), true, far, EntranceError{}, 3.5);
  RecordProperty("blurred", Describe(t));
  EXPECT_GE(t.accuracy(), 0.95) << Describe(t);
  EXPECT_LE(t.wrong, t.ids / 100) << Describe(t);
}

TEST(SlotIdReaderTest, ToleratesEntranceErrors) {
  // About the slot detector's corner error (sim: 3 cm and more far away).
  const Tally t = ReadLot(DefaultReader(), true, Degradation{}, {3.0, 0.035});
  RecordProperty("entrance_error", Describe(t));
  EXPECT_GE(t.accuracy(), 0.95) << Describe(t);
  EXPECT_LE(t.wrong, t.ids / 100) << Describe(t);
}

TEST(SlotIdReaderTest, WrongReadingsAreLessConfident) {
  Degradation hard;
  hard.blur_px = 2.4;
  hard.noise_grey = 10.0;
  hard.contrast = 0.6;
  const Tally t = ReadLot(DefaultReader(), true, hard, {4.0, 0.05}, 3.5);
  RecordProperty("hard", Describe(t));
  ASSERT_GT(t.right, 0);
  EXPECT_GE(static_cast<double>(t.confident_right) / t.confident, 0.98) << Describe(t);
  if (t.wrong > 0) {
    EXPECT_LT(t.confidence_wrong / t.wrong, t.confidence_right / t.right - 0.1) << Describe(t);
  }
}

TEST(SlotIdReaderTest, WornIdsAreNotReadConfidently) {
  const Tally worn = ReadLot(DefaultReader(), false, Degradation{}, EntranceError{});
  RecordProperty("worn", Describe(worn));
  // Read at all (a full reading, however confident): none; the faded paint
  // gives them away next to the slot's lines.
  EXPECT_EQ(worn.right + worn.wrong, 0) << Describe(worn);
  EXPECT_EQ(worn.confident, 0);
}

TEST(SlotIdReaderTest, WornIdsWithoutTheLinesAreMostlyNotReadConfidently) {
  // With the paint check off, only the flakes tell: the classifier's
  // "not a digit" class and hesitation.
  SlotIdReaderOptions options;
  options.min_paint_ratio = 0.0;
  const SlotIdReader reader(options);
  const Tally worn = ReadLot(reader, false, Degradation{}, EntranceError{});
  RecordProperty("worn_no_paint_check", Describe(worn));
  EXPECT_LE(worn.confident, worn.ids / 10) << Describe(worn);
}

TEST(SlotIdReaderTest, ReadingFollowsTheProbabilityThresholds) {
  const SlotIdReaderOptions defaults;
  SlotIdReaderOptions strict;
  strict.min_hypothesis_probability = 0.5;
  const SlotIdReader strict_reader(strict);
  int checked = 0;
  std::uint64_t seed = 100;
  for (const std::string id : {"38", "214", "07", "888"}) {
    for (const Eigen::Vector2d& dir : ScreenDirections()) {
      Degradation blurred;
      blurred.blur_px = 1.5;
      blurred.noise_grey = 5.0;
      const View view = MakeView(SlotWithId(id), true, dir, 3.0, blurred, EntranceError{}, ++seed);
      const SlotIdReading reading = DefaultReader().Read(view.image, view.entrance);
      ASSERT_EQ(reading.digits.size(), id.size());
      for (const DigitReading& digit : reading.digits) {
        if (!digit.read()) continue;
        EXPECT_GE(digit.hypotheses.front().probability, defaults.min_digit_probability);
        for (size_t h = 0; h < digit.hypotheses.size(); ++h) {
          EXPECT_GE(digit.hypotheses[h].probability, defaults.min_hypothesis_probability);
          if (h > 0) {
            EXPECT_LE(digit.hypotheses[h].probability, digit.hypotheses[h - 1].probability);
          }
        }
        ++checked;
      }
      // At most one digit can reach 0.5: one hypothesis per read digit.
      for (const DigitReading& digit : strict_reader.Read(view.image, view.entrance).digits) {
        EXPECT_LE(digit.hypotheses.size(), 1u);
      }
    }
  }
  EXPECT_GT(checked, 50);
}

TEST(SlotIdReaderTest, NothingPaintedGivesAnEmptyReading) {
  const sim::WorldSlot* bare = nullptr;
  for (const sim::WorldSlot& slot : LotSlots()) {
    if (slot.painted_id.empty()) bare = &slot;
  }
  ASSERT_NE(bare, nullptr);
  for (const Eigen::Vector2d& dir : ScreenDirections()) {
    const View view = MakeView(*bare, true, dir, 2.0, Degradation{}, EntranceError{}, 5);
    SlotIdReadDetails details;
    EXPECT_TRUE(DefaultReader().Read(view.image, view.entrance, &details).empty());
    EXPECT_EQ(details.outcome, "no paint");
  }
  const cv::Mat uniform(kTopViewPx, kTopViewPx, CV_8U, cv::Scalar(120));
  EntranceInImage entrance;
  entrance.corner0_px = {250, 300};
  entrance.corner1_px = {400, 300};
  entrance.depth_dir_px = {0, -1};
  EXPECT_TRUE(DefaultReader().Read(uniform, entrance).empty());
}

TEST(SlotIdReaderTest, RegionLeavingTheImageGivesAnEmptyReading) {
  const View view =
      MakeView(SlotWithId("214"), true, {0, -1}, 2.0, Degradation{}, EntranceError{}, 6);
  ASSERT_EQ(DefaultReader().Read(view.image, view.entrance).best(), "214");
  // Cut the image through the ID (between its first and second digit, and
  // through its last digit).
  const Eigen::Vector2d mid = (view.entrance.corner0_px + view.entrance.corner1_px) / 2;
  for (const double cut_px : {-10.0, 25.0}) {
    const int cut = static_cast<int>(mid.x() + cut_px);
    SlotIdReadDetails details;
    EXPECT_TRUE(DefaultReader().Read(view.image.colRange(0, cut), view.entrance, &details).empty())
        << "cut at " << cut_px << ": " << details.outcome;
  }
  // The region entirely outside.
  EntranceInImage away = view.entrance;
  away.corner0_px += Eigen::Vector2d(-800, 0);
  away.corner1_px += Eigen::Vector2d(-800, 0);
  SlotIdReadDetails details;
  EXPECT_TRUE(DefaultReader().Read(view.image, away, &details).empty());
  EXPECT_EQ(details.outcome, "region not seen");
}

TEST(SlotIdReaderTest, IdPartlyUnderTheCarGivesAnEmptyReading) {
  View view = MakeView(SlotWithId("38"), true, {1, 0}, 2.0, Degradation{}, EntranceError{}, 7);
  ASSERT_EQ(DefaultReader().Read(view.image, view.entrance).best(), "38");
  // The car's footprint (0: no camera sees it) over the second digit: the
  // depth points right, so the reading direction points down.
  const Eigen::Vector2d mid = (view.entrance.corner0_px + view.entrance.corner1_px) / 2;
  view.image.rowRange(static_cast<int>(mid.y() + 8), kTopViewPx).setTo(0);
  SlotIdReadDetails details;
  EXPECT_TRUE(DefaultReader().Read(view.image, view.entrance, &details).empty()) << details.outcome;
}

TEST(SlotIdReaderTest, DefacedDigitGivesAPartialReading) {
  const sim::WorldSlot& slot = SlotWithId("38");
  View view = MakeView(slot, true, {0, -1}, 2.0, Degradation{}, EntranceError{}, 8);
  // Paint over the "8" with floor and leave only its top and bottom bars
  // (segments a and d: no digit).
  const render::IdPlacement id = render::PlaceId(slot, render::GroundRasterOptions{});
  const auto pixel_of_map = [&](const Eigen::Vector2d& p_map) {
    const Eigen::Vector2d v = view.T_map_vehicle.inverse() * p_map;
    return Eigen::Vector2d(kCenterPx - v.y() * kPixelsPerM, kCenterPx - v.x() * kPixelsPerM);
  };
  const Eigen::Vector2d foot_left =
      id.center_map - id.right_map * (id.width_m / 2) - id.up_map * (id.height_m / 2) +
      id.right_map * ((font::kDigitWidth + font::kDigitGap) * id.height_m);
  const font::GlyphToPixel to_pixel = [&](double x, double y) {
    return pixel_of_map(foot_left + id.right_map * x + id.up_map * y);
  };
  const double h = id.height_m, t = font::kDigitStroke * h;
  const Eigen::Vector2d floor_probe = pixel_of_map(foot_left + id.up_map * 1.5);
  const double floor_grey = view.image.at<std::uint8_t>(static_cast<int>(floor_probe.y()),
                                                        static_cast<int>(floor_probe.x()));
  // The digit's box and 4 cm around it.
  constexpr double kPadM = 0.04;
  const double w = font::kDigitWidth * h;
  std::vector<cv::Point> box;
  for (const auto& [x, y] : {std::pair{-kPadM, -kPadM}, std::pair{w + kPadM, -kPadM},
                             std::pair{w + kPadM, h + kPadM}, std::pair{-kPadM, h + kPadM}}) {
    const Eigen::Vector2d px = to_pixel(x, y);
    box.emplace_back(static_cast<int>(std::lround(px.x())), static_cast<int>(std::lround(px.y())));
  }
  cv::fillConvexPoly(view.image, box, cv::Scalar(floor_grey));
  cv::Mat bars = cv::Mat::zeros(view.image.size(), CV_8U);
  font::DrawSevenSegments(0b0001001, h, t, to_pixel, 255, &bars);
  view.image.setTo(220, bars);

  const SlotIdReading reading = DefaultReader().Read(view.image, view.entrance);
  ASSERT_EQ(reading.digits.size(), 2u) << reading.best();
  EXPECT_TRUE(reading.partial());
  EXPECT_EQ(reading.best(), "3?");
}

TEST(SlotIdReaderTest, InvalidOptionsAreRejected) {
  std::string error;
  EXPECT_TRUE(SlotIdReaderOptions{}.IsValid(&error)) << error;
  const auto expect_invalid = [](SlotIdReaderOptions options, const std::string& field) {
    std::string why;
    EXPECT_FALSE(options.IsValid(&why)) << field;
    EXPECT_NE(why.find(field), std::string::npos) << why;
    EXPECT_THROW(SlotIdReader{options}, std::invalid_argument) << field;
  };
  SlotIdReaderOptions o;
  o.pixels_per_m = 0.0;
  expect_invalid(o, "pixels_per_m");
  o = {};
  o.id_height_m = -0.6;
  expect_invalid(o, "id_height_m");
  o = {};
  o.pixels_per_m = 15.0;  // 9 px digits
  expect_invalid(o, "id_height_m: must come to at least 12 px at pixels_per_m");
  o = {};
  o.id_setback_m = -0.1;
  expect_invalid(o, "id_setback_m");
  o = {};
  o.max_digits = 0;
  expect_invalid(o, "max_digits");
  o = {};
  o.min_hypothesis_probability = 0.0;
  expect_invalid(o, "min_hypothesis_probability");
  o = {};
  o.min_digit_probability = 0.01;  // below min_hypothesis_probability
  expect_invalid(o, "min_digit_probability");
  o = {};
  o.max_offset_m = -0.1;
  expect_invalid(o, "max_offset_m");
  o = {};
  o.min_paint_ratio = 1.5;
  expect_invalid(o, "min_paint_ratio");

  EXPECT_THROW(DefaultReader().Read(cv::Mat::zeros(600, 600, CV_8UC3), EntranceInImage{}),
               std::invalid_argument);
  EntranceInImage no_direction;
  no_direction.depth_dir_px = Eigen::Vector2d::Zero();
  EXPECT_TRUE(DefaultReader().Read(cv::Mat::zeros(600, 600, CV_8U), no_direction).empty());
}

// ---------------------------------------------------------------------------
// The default lot in rendered, fused top views (render::Renderer and
// camera::TopViewFusion with the default rig) along the default drive: every
// slot whose ID box lies inside the top view and outside the car's
// footprint, its entrance from the true pose. The target: 95 % of
// the readable IDs read right.

TEST(SlotIdReaderTest, ReadsTheDefaultLotInRenderedTopViews) {
  const sim::ScenarioConfig scenario = sim::DefaultScenario();
  const sim::World world = sim::BuildWorld(scenario.world);
  const camera::CameraRig rig = camera::DefaultRig();
  const render::Renderer renderer(world, rig, render::RenderOptions{}, 1);
  const std::vector<std::string> fisheyes = {"front", "rear", "left", "right"};
  const camera::TopViewFusion fusion(rig, fisheyes);
  const std::vector<sim::VehicleState> drive = sim::DriveRoute(scenario.route, scenario.vehicle, 1);

  Tally legible, worn;
  double driven_m = 0.0, last_frame_m = -1e9;
  int frames = 0;
  for (size_t i = 1; i < drive.size(); ++i) {
    driven_m +=
        (drive[i].T_map_vehicle.translation() - drive[i - 1].T_map_vehicle.translation()).norm();
    if (driven_m - last_frame_m < 6.0) continue;
    last_frame_m = driven_m;
    ++frames;
    const SE2& T_map_vehicle = drive[i].T_map_vehicle;
    const cv::Mat top = fusion.Fuse(renderer.RenderAll(T_map_vehicle, drive[i].t_ns, fisheyes));
    const auto pixel_of = [&](const Eigen::Vector2d& p_map) {
      return fusion.VehicleToPixel(T_map_vehicle.inverse() * p_map);
    };
    for (const sim::WorldSlot& slot : world.slots) {
      if (slot.painted_id.empty()) continue;
      // The ID's box, sampled: inside the image and seen by a camera.
      const render::IdPlacement id = render::PlaceId(slot, renderer.ground().options());
      bool visible = true;
      for (double a = -0.5; a <= 0.5 && visible; a += 0.1) {
        for (double b = -0.5; b <= 0.5 && visible; b += 0.1) {
          const Eigen::Vector2d px = pixel_of(id.center_map + id.right_map * (a * id.width_m) +
                                              id.up_map * (b * id.height_m));
          visible = px.x() >= 0 && px.y() >= 0 && px.x() <= kTopViewPx - 1 &&
                    px.y() <= kTopViewPx - 1 &&
                    top.at<std::uint8_t>(static_cast<int>(px.y()), static_cast<int>(px.x())) != 0;
        }
      }
      if (!visible) continue;
      EntranceInImage entrance;
      entrance.corner0_px = pixel_of(slot.corners_map[0]);
      entrance.corner1_px = pixel_of(slot.corners_map[1]);
      entrance.depth_dir_px = (pixel_of((slot.corners_map[2] + slot.corners_map[3]) / 2) -
                               (entrance.corner0_px + entrance.corner1_px) / 2)
                                  .normalized();
      (slot.id_legible ? legible : worn).Add(DefaultReader().Read(top, entrance), slot.painted_id);
    }
  }
  RecordProperty("frames", std::to_string(frames));
  RecordProperty("legible", Describe(legible));
  RecordProperty("worn", Describe(worn));
  std::cout << "rendered top views: " << frames << " frames; legible IDs: " << Describe(legible)
            << " (" << 100.0 * legible.accuracy() << " % right); worn IDs: " << Describe(worn)
            << "\n";
  EXPECT_GT(legible.ids, 300);
  EXPECT_GE(legible.accuracy(), 0.95) << Describe(legible);
  EXPECT_LE(legible.wrong, legible.ids / 100) << Describe(legible);
  EXPECT_GT(worn.ids, 10);
  EXPECT_LE(worn.confident, worn.ids / 10) << Describe(worn);
}

}  // namespace
}  // namespace parkslam::perception
