#include "parkslam/sim/sensor_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "parkslam/common/angles.h"
#include "parkslam/sim/compass_field.h"
#include "parkslam/sim/simulator.h"

namespace parkslam::sim {
namespace {

TEST(IdReadingTest, ObservedOutcomeRatesMatchConfigured) {
  IdSensorConfig config;
  config.confusion_rate = 0.2;
  config.partial_rate = 0.1;
  config.unreadable_rate = 0.05;
  Random rng(4);
  const int n = 40000;
  int confused = 0, partial = 0, unreadable = 0;
  for (int i = 0; i < n; ++i) {
    const SlotIdReading r = SimulateIdReading("38", config, rng);
    if (r.empty()) {
      ++unreadable;
    } else if (r.partial()) {
      ++partial;
    } else if (r.best() != "38") {
      ++confused;
    }
  }
  // Binomial standard error at n = 40000 is at most 0.0025; allow 4 of them.
  EXPECT_NEAR(confused / double(n), 0.2, 0.01);
  EXPECT_NEAR(partial / double(n), 0.1, 0.01);
  EXPECT_NEAR(unreadable / double(n), 0.05, 0.01);
}

TEST(IdReadingTest, ConfusionUsesConfusableDigits) {
  IdSensorConfig config;
  config.confusion_rate = 1.0;
  config.partial_rate = config.unreadable_rate = 0.0;
  Random rng(8);
  for (int i = 0; i < 200; ++i) {
    const std::string best = SimulateIdReading("39", config, rng).best();
    ASSERT_EQ(best.size(), 2u);
    const bool first_wrong = best[0] != '3', second_wrong = best[1] != '9';
    ASSERT_NE(first_wrong, second_wrong) << best;  // exactly one digit wrong
    if (first_wrong) {
      EXPECT_NE(ConfusableDigits('3').find(best[0]), std::string::npos);
    }
    if (second_wrong) {
      EXPECT_NE(ConfusableDigits('9').find(best[1]), std::string::npos);
    }
  }
}

TEST(IdReadingTest, TrueDigitIsSecondHypothesisAtConfiguredRate) {
  IdSensorConfig config;
  config.confusion_rate = 1.0;
  config.partial_rate = config.unreadable_rate = 0.0;
  config.true_digit_second_rate = 0.7;
  Random rng(9);
  int second_true = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const SlotIdReading r = SimulateIdReading("5", config, rng);
    second_true += r.digits[0].hypotheses.at(1).digit == '5';
  }
  EXPECT_NEAR(second_true / double(n), 0.7, 0.015);
}

TEST(IdReadingTest, ProbabilitiesAreSortedAndSumBelowOne) {
  IdSensorConfig config;
  config.confusion_rate = 0.5;
  Random rng(10);
  for (int i = 0; i < 1000; ++i) {
    for (const DigitReading& d : SimulateIdReading("107", config, rng).digits) {
      double sum = 0.0;
      for (size_t k = 0; k < d.hypotheses.size(); ++k) {
        sum += d.hypotheses[k].probability;
        if (k > 0) {
          EXPECT_LE(d.hypotheses[k].probability, d.hypotheses[k - 1].probability);
        }
      }
      EXPECT_LE(sum, 1.0 + 1e-12);
    }
  }
}

World OneSlotWorld(const Eigen::Vector2d& c0) {
  World world;
  WorldSlot slot;
  slot.corners_map = {c0, c0 + Eigen::Vector2d(2.5, 0), c0 + Eigen::Vector2d(2.5, 5.3),
                      c0 + Eigen::Vector2d(0, 5.3)};
  slot.painted_id = "38";
  world.slots.push_back(slot);
  return world;
}

TEST(SlotSensorTest, SeenOnlyWhenEntranceInsideTopView) {
  SensorConfig config;
  config.slots.miss_rate = 0.0;
  config.slots.false_per_frame = 0.0;
  Random rng(1);
  std::vector<int> labels;
  // View: x in [1.4 - 5, 1.4 + 5], y in [-5, 5] around the rear axle.
  const World inside = OneSlotWorld({2.0, 1.0});
  EXPECT_EQ(SimulateSlotFrame(inside, SE2(), 0, config, rng, &labels).slots.size(), 1u);
  EXPECT_EQ(labels, std::vector<int>{0});
  const World outside = OneSlotWorld({5.0, 1.0});  // corner 1 at x = 7.5 > 6.4
  EXPECT_TRUE(SimulateSlotFrame(outside, SE2(), 0, config, rng, &labels).slots.empty());
}

TEST(SlotSensorTest, FarCornersGuessedAtStandardDepthWhenOutOfView) {
  SensorConfig config;
  config.slots.miss_rate = 0.0;
  config.slots.false_per_frame = 0.0;
  config.slots.corner_sigma_m = config.slots.corner_sigma_per_m = 0.0;
  config.slots.far_direction_sigma_deg = 0.0;
  Random rng(1);
  std::vector<int> labels;
  const World world = OneSlotWorld({2.0, 1.0});  // far corners at y = 6.3 > 5
  const auto frame = SimulateSlotFrame(world, SE2(), 0, config, rng, &labels);
  ASSERT_EQ(frame.slots.size(), 1u);
  const SlotObservation& obs = frame.slots[0];
  EXPECT_TRUE(obs.corner_observed[0] && obs.corner_observed[1]);
  EXPECT_FALSE(obs.corner_observed[2] || obs.corner_observed[3]);
  EXPECT_NEAR((obs.corners_vehicle[3] - Eigen::Vector2d(2.0, 6.3)).norm(), 0.0, 1e-9);
}

TEST(SlotSensorTest, MissAndFalseRatesMatch) {
  SensorConfig config;
  config.slots.miss_rate = 0.2;
  config.slots.false_per_frame = 0.1;
  Random rng(2);
  const World world = OneSlotWorld({2.0, 1.0});
  std::vector<int> labels;
  int seen = 0, false_detections = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    SimulateSlotFrame(world, SE2(), 0, config, rng, &labels);
    for (int label : labels) (label == 0 ? seen : false_detections)++;
  }
  EXPECT_NEAR(seen / double(n), 0.8, 0.015);
  EXPECT_NEAR(false_detections / double(n), 0.1, 0.01);
}

TEST(SlotSensorTest, CornerNoiseHasConfiguredSigma) {
  SensorConfig config;
  config.slots.miss_rate = 0.0;
  config.slots.false_per_frame = 0.0;
  config.slots.corner_sigma_m = 0.04;
  config.slots.corner_sigma_per_m = 0.0;
  Random rng(3);
  const World world = OneSlotWorld({2.0, 1.0});
  std::vector<int> labels;
  double sum2 = 0;
  const int n = 5000;
  for (int i = 0; i < n; ++i) {
    const auto frame = SimulateSlotFrame(world, SE2(), 0, config, rng, &labels);
    sum2 += (frame.slots[0].corners_vehicle[0] - Eigen::Vector2d(2.0, 1.0)).squaredNorm();
  }
  EXPECT_NEAR(std::sqrt(sum2 / (2 * n)), 0.04, 0.002);
}

World OneTagWorld(const Eigen::Vector2d& p, double normal_yaw) {
  World world;
  world.tags.push_back({3, p, normal_yaw, 0.488, false, -1});
  return world;
}

TagSensorConfig PerfectTagConfig() {
  TagSensorConfig config;
  config.miss_rate = config.miss_rate_at_max_range = 0.0;
  config.camera_x_m = config.camera_y_m = 0.0;
  return config;
}

TEST(TagSensorTest, NothingAtTwentyMetresOrBeyond) {
  const TagSensorConfig config = PerfectTagConfig();
  Random rng(1);
  EXPECT_EQ(SimulateTagFrame(OneTagWorld({19.9, 0}, kPi), SE2(), 0, config, rng).tags.size(), 1u);
  EXPECT_TRUE(SimulateTagFrame(OneTagWorld({20.0, 0}, kPi), SE2(), 0, config, rng).tags.empty());
}

TEST(TagSensorTest, OutsideFieldOfViewOrSeenFromBehindIsNotDetected) {
  const TagSensorConfig config = PerfectTagConfig();  // 90 degree field of view
  Random rng(1);
  EXPECT_EQ(SimulateTagFrame(OneTagWorld({5, 4.9}, -2.0), SE2(), 0, config, rng).tags.size(), 1u);
  EXPECT_TRUE(SimulateTagFrame(OneTagWorld({5, 5.1}, -2.0), SE2(), 0, config, rng).tags.empty());
  EXPECT_TRUE(SimulateTagFrame(OneTagWorld({5, 0}, 0.0), SE2(), 0, config, rng).tags.empty());
}

TEST(TagSensorTest, PillarOccludesTag) {
  const TagSensorConfig config = PerfectTagConfig();
  Random rng(1);
  World world = OneTagWorld({10, 0}, kPi);
  world.pillars.push_back({{5, 0}, 0.3});
  EXPECT_TRUE(SimulateTagFrame(world, SE2(), 0, config, rng).tags.empty());
  world.pillars[0].center_map = {5, 1.0};
  EXPECT_EQ(SimulateTagFrame(world, SE2(), 0, config, rng).tags.size(), 1u);
}

TEST(TagSensorTest, NoiseGrowsWithRangeAsConfigured) {
  TagSensorConfig config = PerfectTagConfig();
  Random rng(5);
  for (double range : {4.0, 16.0}) {
    double sum2 = 0;
    const int n = 4000;
    for (int i = 0; i < n; ++i) {
      const auto frame = SimulateTagFrame(OneTagWorld({range, 0}, kPi), SE2(), 0, config, rng);
      sum2 += std::pow(frame.tags.at(0).range_m - range, 2);
    }
    const double expected = config.range_sigma_m + config.range_sigma_per_m * range;
    EXPECT_NEAR(std::sqrt(sum2 / n), expected, 0.05 * expected) << range;
  }
}

TEST(TagSensorTest, PointInVehicleFrameAccountsForCameraMount) {
  TagSensorConfig config = PerfectTagConfig();
  config.camera_x_m = 1.8;
  config.range_sigma_m = config.range_sigma_per_m = 0.0;
  config.bearing_sigma_rad = config.bearing_sigma_per_m = 0.0;
  config.yaw_sigma_rad = config.yaw_sigma_per_m = 0.0;
  Random rng(1);
  // Vehicle at (10, 0) facing +y; the tag 8 m ahead of it faces back.
  const auto frame =
      SimulateTagFrame(OneTagWorld({10, 8}, -kPi / 2), SE2(10, 0, kPi / 2), 0, config, rng);
  ASSERT_EQ(frame.tags.size(), 1u);
  EXPECT_NEAR(frame.tags[0].p_vehicle.x(), 8.0, 1e-9);
  EXPECT_NEAR(frame.tags[0].p_vehicle.y(), 0.0, 1e-9);
  EXPECT_NEAR(frame.tags[0].range_m, 6.2, 1e-9);
  EXPECT_NEAR(std::abs(frame.tags[0].yaw_vehicle_rad), kPi, 1e-9);
}

TEST(OdometrySensorTest, GyroBiasAndNoiseAsConfigured) {
  std::vector<VehicleState> states(60001);
  for (size_t i = 0; i < states.size(); ++i) states[i].t_ns = FromSeconds(i * 0.01);
  OdometrySensorConfig config;
  config.gyro_bias_walk_radps_per_sqrt_s = 0.0;
  VehicleParameters vehicle;
  // The drive-constant gyro bias is drawn per seed: its spread over seeds
  // matches gyro_bias_sigma_radps; the white noise matches gyro_sigma_radps.
  double bias2 = 0, noise2 = 0;
  int noise_n = 0;
  const int seeds = 200;
  for (int seed = 0; seed < seeds; ++seed) {
    SensorLog log;
    std::vector<VehicleState> short_states(states.begin(), states.begin() + 2001);
    SimulateOdometrySensors(short_states, config, vehicle, seed, &log);
    double mean = 0;
    for (const ImuSample& s : log.imu_samples) mean += s.yaw_rate_radps;
    mean /= log.imu_samples.size();
    bias2 += mean * mean;
    for (const ImuSample& s : log.imu_samples) {
      noise2 += std::pow(s.yaw_rate_radps - mean, 2);
      ++noise_n;
    }
  }
  EXPECT_NEAR(std::sqrt(bias2 / seeds), config.gyro_bias_sigma_radps, 0.0006);
  EXPECT_NEAR(std::sqrt(noise2 / noise_n), config.gyro_sigma_radps, 0.0001);
}

// The default drive's true states, once for the compass tests.
const Simulation& DefaultDrive() {
  static const Simulation sim = [] {
    ScenarioConfig scenario = DefaultScenario();
    scenario.sensors.compass.model = "clean";
    return Simulate(scenario, 1);
  }();
  return sim;
}

TEST(CompassFieldTest, SteelBendsTheHeadingBySeveralDegreesSlowlyAlongTheDrive) {
  const Simulation& sim = DefaultDrive();
  const CompassField field(sim.world, CompassConfig{}, 1);
  EXPECT_GT(field.steel_sources(), 60);  // the pillars and about half the slots
  double sum2 = 0.0, max_abs = 0.0, max_step = 0.0;
  int n = 0;
  Eigen::Vector2d last = sim.states.front().T_map_vehicle.translation();
  double last_d = field.DisturbanceAt(last);
  for (const VehicleState& state : sim.states) {
    const Eigen::Vector2d p = state.T_map_vehicle.translation();
    const double d = field.DisturbanceAt(p);
    sum2 += d * d;
    max_abs = std::max(max_abs, std::abs(d));
    ++n;
    const double moved_m = (p - last).norm();
    if (moved_m >= 0.1) {
      // Per 10 cm driven: a bend that grows over metres, not a jitter.
      max_step = std::max(max_step, std::abs(d - last_d) / moved_m * 0.1);
      last = p;
      last_d = d;
    }
  }
  const double rms_deg = std::sqrt(sum2 / n) * 180.0 / M_PI;
  EXPECT_GT(rms_deg, 2.0);
  EXPECT_LT(rms_deg, 8.0);
  EXPECT_GT(max_abs * 180.0 / M_PI, 6.0);
  EXPECT_LT(max_step * 180.0 / M_PI, 1.0);
  // The clean and gyro-only models bend nothing.
  CompassConfig clean;
  clean.model = "clean";
  EXPECT_EQ(CompassField(sim.world, clean, 1).DisturbanceAt({10.0, 10.0}), 0.0);
  EXPECT_EQ(CompassField().DisturbanceAt({10.0, 10.0}), 0.0);
}

TEST(CompassFieldTest, ModelsChangeOnlyTheHeading) {
  const Simulation& sim = DefaultDrive();
  std::vector<VehicleState> states(sim.states.begin(), sim.states.begin() + 3000);
  SensorConfig sensors;
  SensorLog disturbed, clean, none;
  const auto simulate = [&](const std::string& model, SensorLog* log) {
    sensors.compass.model = model;
    SimulateOdometrySensors(
        states, MakeOdometrySensorModel(sensors, VehicleParameters{}, sim.world, 7), log);
  };
  simulate("disturbed", &disturbed);
  simulate("clean", &clean);
  simulate("none", &none);
  ASSERT_EQ(disturbed.imu_samples.size(), clean.imu_samples.size());
  ASSERT_EQ(none.imu_samples.size(), clean.imu_samples.size());
  double largest_bend = 0.0;
  for (size_t k = 0; k < clean.imu_samples.size(); ++k) {
    EXPECT_EQ(disturbed.imu_samples[k].yaw_rate_radps, clean.imu_samples[k].yaw_rate_radps);
    EXPECT_EQ(none.imu_samples[k].yaw_rate_radps, clean.imu_samples[k].yaw_rate_radps);
    EXPECT_FALSE(none.imu_samples[k].heading_rad.has_value());
    ASSERT_TRUE(disturbed.imu_samples[k].heading_rad && clean.imu_samples[k].heading_rad);
    largest_bend = std::max(largest_bend, std::abs(AngleDiff(*disturbed.imu_samples[k].heading_rad,
                                                             *clean.imu_samples[k].heading_rad)));
  }
  EXPECT_GT(largest_bend, 0.01);
  EXPECT_EQ(disturbed.wheel_speeds.size(), none.wheel_speeds.size());
}

VehicleState StateWith(double speed_mps, double road_wheel_angle_rad) {
  VehicleState state;
  state.speed_mps = speed_mps;
  state.road_wheel_angle_rad = road_wheel_angle_rad;
  return state;
}

TEST(OdometrySensorModelTest, WheelScaleAndNoiseAsConfigured) {
  OdometrySensorConfig config;  // scale sigma 0.003, noise sigma 0.02 m/s
  const VehicleState state = StateWith(2.0, 0.0);
  // The per-drive scale error is drawn per seed: the spread over seeds of
  // the mean reading matches 2 m/s * wheel_speed_scale_sigma.
  double scale2 = 0, noise2 = 0;
  int noise_n = 0;
  const int seeds = 300, samples = 400;
  for (int seed = 0; seed < seeds; ++seed) {
    OdometrySensorModel model(config, VehicleParameters{}, seed);
    std::vector<double> readings;
    for (int k = 0; k < samples; ++k) readings.push_back(model.MeasureWheel(state, k).speed_mps);
    double mean = 0;
    for (double r : readings) mean += r / samples;
    scale2 += std::pow(mean / 2.0 - 1.0, 2);
    for (double r : readings) {
      noise2 += std::pow(r - mean, 2);
      ++noise_n;
    }
  }
  // Standard errors: about 0.00013 of the scale sigma (including the
  // 0.02 / sqrt(400) / 2 of the white noise left in each mean), 0.00004 of
  // the noise sigma.
  EXPECT_NEAR(std::sqrt(scale2 / seeds), std::hypot(0.003, 0.02 / 20 / 2), 0.0005);
  EXPECT_NEAR(std::sqrt(noise2 / noise_n), config.wheel_speed_sigma_mps, 0.0002);
}

TEST(OdometrySensorModelTest, SteeringIsRatioTimesRoadWheelAngle) {
  OdometrySensorConfig config;  // 0.01 rad at the steering wheel
  VehicleParameters vehicle;
  vehicle.steering_ratio = 15.0;
  OdometrySensorModel model(config, vehicle, 1);
  const int n = 10000;
  double sum = 0, sum2 = 0;
  for (int k = 0; k < n; ++k) {
    const double r = model.MeasureSteering(StateWith(0.0, 0.1), k).steering_wheel_rad;
    sum += r;
    sum2 += (r - 1.5) * (r - 1.5);
  }
  EXPECT_NEAR(sum / n, 1.5, 0.0005);  // 5 standard errors of the mean
  EXPECT_NEAR(std::sqrt(sum2 / n), config.steering_wheel_sigma_rad, 0.0005);
}

TEST(OdometrySensorModelTest, GyroBiasWalksBySqrtOfElapsedTime) {
  OdometrySensorConfig config;
  config.gyro_sigma_radps = 0.0;
  config.gyro_bias_sigma_radps = 0.0;
  config.gyro_bias_walk_radps_per_sqrt_s = 0.001;
  const VehicleState state;
  // After 100 s in steps of dt_s the bias has spread to 0.001 * sqrt(100),
  // whatever the step; a step of 0 leaves it where it is.
  for (double dt_s : {0.01, 0.1}) {
    double sum2 = 0;
    const int seeds = 400;
    for (int seed = 0; seed < seeds; ++seed) {
      OdometrySensorModel model(config, VehicleParameters{}, seed);
      const int steps = static_cast<int>(std::lround(100.0 / dt_s));
      for (int k = 0; k < steps; ++k) model.MeasureImu(state, k, dt_s);
      const double bias = model.MeasureImu(state, steps, 0.0).yaw_rate_radps;
      EXPECT_EQ(model.MeasureImu(state, steps, 0.0).yaw_rate_radps, bias);
      sum2 += bias * bias;
    }
    // Standard error of the estimated sigma: 0.01 / sqrt(800) = 0.00035.
    EXPECT_NEAR(std::sqrt(sum2 / seeds), 0.01, 0.0015) << dt_s;
  }
}

}  // namespace
}  // namespace parkslam::sim
