#include "parkslam/io/dataset.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "parkslam/common/angles.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/test_util.h"

namespace parkslam::io {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using ::testing::Not;
using testing::TempDir;

DigitReading Digit(std::vector<DigitHypothesis> hypotheses) { return {std::move(hypotheses)}; }

SlotObservation Slot(double x, SlotIdReading id) {
  SlotObservation slot;
  slot.corners_vehicle = {Eigen::Vector2d(x, 1.5), Eigen::Vector2d(x + 2.5, 1.5),
                          Eigen::Vector2d(x + 2.5, 6.8), Eigen::Vector2d(x, 6.8)};
  slot.corner_observed = {true, true, false, true};
  slot.corner_sigma_m = 0.031;
  slot.detection_confidence = 0.875;
  slot.id = std::move(id);
  return slot;
}

TagObservation Tag(int id, double x) {
  TagObservation tag;
  tag.tag_id = id;
  tag.p_vehicle = Eigen::Vector2d(x, -0.4);
  tag.range_m = std::hypot(x - 1.8, 0.7);
  tag.bearing_rad = -0.1234567890123;
  tag.yaw_vehicle_rad = 3.0;
  tag.covariance_vehicle << 0.0004, -0.0001, -0.0001, 0.0009;
  tag.yaw_sigma_rad = 0.03;
  return tag;
}

// A small dataset with every kind of record: full, partial and empty ID
// readings, frames without detections, and all ground truth.
Dataset SampleDataset() {
  Dataset d;
  d.name = "hand-made";
  d.seed = 18'446'744'073'709'551'615ULL;  // the largest seed
  d.created_by = "io test";
  sim::ScenarioConfig scenario = sim::DefaultScenario();
  scenario.world.name = "test lot";
  scenario.route.laps = 1;
  SetScenario(scenario, &d);
  SensorLog& log = d.log;
  log.wheel_speeds = {{0, 1.25}, {20'000'000, -0.5}, {40'000'000, 1e-7}};
  log.steering_angles = {{0, 0.1}, {20'000'000, -3.3}};
  log.imu_samples = {{0, 0.01, -3.14159}, {10'000'000, 0.1 + 0.2, 3.1}};
  const SlotIdReading full{{Digit({{'3', 0.8}, {'8', 0.15}}), Digit({{'9', 0.9}})}};
  const SlotIdReading partial{{Digit({{'1', 0.6}}), Digit({})}};
  log.slot_frames = {{100'000'000, {Slot(1.0, full), Slot(-4.0, partial)}},
                     {200'000'000, {Slot(0.5, SlotIdReading{})}},
                     {300'000'000, {}}};
  log.tag_frames = {{100'000'000, {Tag(7, 5.1), Tag(12, 9.0)}}, {250'000'000, {}}};
  d.groundtruth_trajectory = {{0, SE2(-37.0, 9.1, 0.0)},
                              {10'000'000, SE2(-36.99, 9.1001, 0.001)},
                              {20'000'000, SE2(-36.98, 9.1003, 0.002)}};
  SemanticMap map;
  map.metadata = {{"source", "test"}};
  for (int i = 0; i < 3; ++i) {
    MapSlot slot;
    slot.id = std::to_string(38 + i);
    slot.corners_map = {Eigen::Vector2d(2.5 * i, 0), Eigen::Vector2d(2.5 * i + 2.5, 0),
                        Eigen::Vector2d(2.5 * i + 2.5, 5.3), Eigen::Vector2d(2.5 * i, 5.3)};
    map.slots.push_back(slot);
  }
  d.groundtruth_map = map;
  d.slot_labels = {{0, -1}, {2}, {}};
  return d;
}

void ExpectSlotsEqual(const SlotObservation& a, const SlotObservation& b) {
  for (int c = 0; c < kSlotCorners; ++c) {
    EXPECT_EQ(a.corners_vehicle[c], b.corners_vehicle[c]);
    EXPECT_EQ(a.corner_observed[c], b.corner_observed[c]);
  }
  EXPECT_EQ(a.corner_sigma_m, b.corner_sigma_m);
  EXPECT_EQ(a.detection_confidence, b.detection_confidence);
  ASSERT_EQ(a.id.digits.size(), b.id.digits.size());
  for (std::size_t d = 0; d < a.id.digits.size(); ++d) {
    const auto& ha = a.id.digits[d].hypotheses;
    const auto& hb = b.id.digits[d].hypotheses;
    ASSERT_EQ(ha.size(), hb.size());
    for (std::size_t h = 0; h < ha.size(); ++h) {
      EXPECT_EQ(ha[h].digit, hb[h].digit);
      EXPECT_EQ(ha[h].probability, hb[h].probability);
    }
  }
}

void ExpectDatasetsEqual(const Dataset& a, const Dataset& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.created_by, b.created_by);
  EXPECT_EQ(a.vehicle.wheelbase_m, b.vehicle.wheelbase_m);
  EXPECT_EQ(a.vehicle.steering_ratio, b.vehicle.steering_ratio);
  EXPECT_EQ(a.odometry_spec.gyro_sigma_radps, b.odometry_spec.gyro_sigma_radps);
  EXPECT_EQ(a.odometry_spec.imu_rate_hz, b.odometry_spec.imu_rate_hz);
  ASSERT_EQ(a.scenario.has_value(), b.scenario.has_value());
  if (a.scenario) {
    EXPECT_EQ(a.scenario->world.name, b.scenario->world.name);
    EXPECT_EQ(a.scenario->route.laps, b.scenario->route.laps);
    EXPECT_EQ(a.scenario->world.rows.size(), b.scenario->world.rows.size());
    EXPECT_EQ(a.scenario->route.loop_m, b.scenario->route.loop_m);
  }

  ASSERT_EQ(a.log.wheel_speeds.size(), b.log.wheel_speeds.size());
  for (std::size_t i = 0; i < a.log.wheel_speeds.size(); ++i) {
    EXPECT_EQ(a.log.wheel_speeds[i].t_ns, b.log.wheel_speeds[i].t_ns);
    EXPECT_EQ(a.log.wheel_speeds[i].speed_mps, b.log.wheel_speeds[i].speed_mps);
  }
  ASSERT_EQ(a.log.steering_angles.size(), b.log.steering_angles.size());
  for (std::size_t i = 0; i < a.log.steering_angles.size(); ++i) {
    EXPECT_EQ(a.log.steering_angles[i].t_ns, b.log.steering_angles[i].t_ns);
    EXPECT_EQ(a.log.steering_angles[i].steering_wheel_rad,
              b.log.steering_angles[i].steering_wheel_rad);
  }
  ASSERT_EQ(a.log.imu_samples.size(), b.log.imu_samples.size());
  for (std::size_t i = 0; i < a.log.imu_samples.size(); ++i) {
    EXPECT_EQ(a.log.imu_samples[i].t_ns, b.log.imu_samples[i].t_ns);
    EXPECT_EQ(a.log.imu_samples[i].yaw_rate_radps, b.log.imu_samples[i].yaw_rate_radps);
    EXPECT_EQ(a.log.imu_samples[i].heading_rad, b.log.imu_samples[i].heading_rad);
  }
  ASSERT_EQ(a.log.slot_frames.size(), b.log.slot_frames.size());
  for (std::size_t f = 0; f < a.log.slot_frames.size(); ++f) {
    EXPECT_EQ(a.log.slot_frames[f].t_ns, b.log.slot_frames[f].t_ns);
    ASSERT_EQ(a.log.slot_frames[f].slots.size(), b.log.slot_frames[f].slots.size());
    for (std::size_t i = 0; i < a.log.slot_frames[f].slots.size(); ++i) {
      ExpectSlotsEqual(a.log.slot_frames[f].slots[i], b.log.slot_frames[f].slots[i]);
    }
  }
  ASSERT_EQ(a.log.tag_frames.size(), b.log.tag_frames.size());
  for (std::size_t f = 0; f < a.log.tag_frames.size(); ++f) {
    EXPECT_EQ(a.log.tag_frames[f].t_ns, b.log.tag_frames[f].t_ns);
    ASSERT_EQ(a.log.tag_frames[f].tags.size(), b.log.tag_frames[f].tags.size());
    for (std::size_t i = 0; i < a.log.tag_frames[f].tags.size(); ++i) {
      const TagObservation& ta = a.log.tag_frames[f].tags[i];
      const TagObservation& tb = b.log.tag_frames[f].tags[i];
      EXPECT_EQ(ta.tag_id, tb.tag_id);
      EXPECT_EQ(ta.p_vehicle, tb.p_vehicle);
      EXPECT_EQ(ta.range_m, tb.range_m);
      EXPECT_EQ(ta.bearing_rad, tb.bearing_rad);
      EXPECT_EQ(ta.yaw_vehicle_rad, tb.yaw_vehicle_rad);
      EXPECT_EQ(ta.covariance_vehicle, tb.covariance_vehicle);
      EXPECT_EQ(ta.yaw_sigma_rad, tb.yaw_sigma_rad);
    }
  }
  ASSERT_EQ(a.groundtruth_trajectory.size(), b.groundtruth_trajectory.size());
  for (std::size_t i = 0; i < a.groundtruth_trajectory.size(); ++i) {
    EXPECT_EQ(a.groundtruth_trajectory[i].t_ns, b.groundtruth_trajectory[i].t_ns);
    EXPECT_NEAR(a.groundtruth_trajectory[i].T_map_vehicle.x(),
                b.groundtruth_trajectory[i].T_map_vehicle.x(), 5e-7);
    EXPECT_NEAR(a.groundtruth_trajectory[i].T_map_vehicle.y(),
                b.groundtruth_trajectory[i].T_map_vehicle.y(), 5e-7);
    EXPECT_NEAR(AngleDiff(a.groundtruth_trajectory[i].T_map_vehicle.yaw(),
                          b.groundtruth_trajectory[i].T_map_vehicle.yaw()),
                0.0, 1e-9);
  }
  ASSERT_EQ(a.groundtruth_map.has_value(), b.groundtruth_map.has_value());
  if (a.groundtruth_map) {
    ASSERT_EQ(a.groundtruth_map->slots.size(), b.groundtruth_map->slots.size());
    for (std::size_t i = 0; i < a.groundtruth_map->slots.size(); ++i) {
      EXPECT_EQ(a.groundtruth_map->slots[i].id, b.groundtruth_map->slots[i].id);
      EXPECT_NEAR(
          (a.groundtruth_map->slots[i].corners_map[2] - b.groundtruth_map->slots[i].corners_map[2])
              .norm(),
          0.0, 5e-4);
    }
    EXPECT_EQ(a.groundtruth_map->metadata, b.groundtruth_map->metadata);
  }
  EXPECT_EQ(a.slot_labels, b.slot_labels);
}

// Replaces the first occurrence of `from` by `to` in a file of the dataset.
void EditFile(const std::filesystem::path& file, const std::string& from, const std::string& to) {
  std::string content = ReadTextFile(file);
  const std::size_t at = content.find(from);
  ASSERT_NE(at, std::string::npos) << from << " not in " << file;
  content.replace(at, from.size(), to);
  WriteFileAtomically(file, content);
}

TEST(DatasetTest, RoundTripKeepsEveryRecord) {
  const TempDir dir;
  const Dataset original = SampleDataset();
  WriteDataset(dir / "d", original);
  ExpectDatasetsEqual(ReadDataset(dir / "d"), original);
}

TEST(DatasetTest, RoundTripWithoutGroundTruth) {
  const TempDir dir;
  Dataset original = SampleDataset();
  original.groundtruth_trajectory.clear();
  original.groundtruth_map.reset();
  original.slot_labels.clear();
  WriteDataset(dir / "d", original);
  const Dataset read = ReadDataset(dir / "d");
  ExpectDatasetsEqual(read, original);
  EXPECT_FALSE(std::filesystem::exists(dir / "d/groundtruth/map.json"));
}

TEST(DatasetTest, RewritingWithoutGroundTruthRemovesTheOldFiles) {
  const TempDir dir;
  Dataset dataset = SampleDataset();
  WriteDataset(dir / "d", dataset);
  ASSERT_TRUE(std::filesystem::exists(dir / "d/groundtruth/trajectory.tum"));
  dataset.groundtruth_trajectory.clear();
  dataset.groundtruth_map.reset();
  dataset.slot_labels.clear();
  WriteDataset(dir / "d", dataset);
  EXPECT_FALSE(std::filesystem::exists(dir / "d/groundtruth/trajectory.tum"));
  EXPECT_FALSE(std::filesystem::exists(dir / "d/groundtruth/map.json"));
  EXPECT_FALSE(std::filesystem::exists(dir / "d/groundtruth/slot_labels.jsonl"));
  EXPECT_FALSE(ReadDataset(dir / "d").groundtruth_map.has_value());
}

TEST(DatasetTest, WritesTheDocumentedFileContents) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EXPECT_EQ(ReadTextFile(dir / "d/sensors/wheel_speed.csv"),
            "t_ns,speed_mps\n0,1.25\n20000000,-0.5\n40000000,1e-07\n");
  EXPECT_EQ(ReadTextFile(dir / "d/sensors/steering.csv"),
            "t_ns,steering_wheel_rad\n0,0.1\n20000000,-3.3\n");
  EXPECT_EQ(ReadTextFile(dir / "d/sensors/imu.csv"),
            "t_ns,yaw_rate_radps,heading_rad\n0,0.01,-3.14159\n"
            "10000000,0.30000000000000004,3.1\n");
  EXPECT_EQ(ReadTextFile(dir / "d/groundtruth/slot_labels.jsonl"),
            "{\"t_ns\":100000000,\"slots\":[0,-1]}\n{\"t_ns\":200000000,\"slots\":[2]}\n"
            "{\"t_ns\":300000000,\"slots\":[]}\n");
  const std::string slots = ReadTextFile(dir / "d/observations/slots.jsonl");
  EXPECT_THAT(slots, HasSubstr("\"id\":[[[\"3\",0.8],[\"8\",0.15]],[[\"9\",0.9]]]"));
  EXPECT_THAT(slots, HasSubstr("\"id\":[[[\"1\",0.6]],[]]"));
  EXPECT_THAT(slots, HasSubstr("{\"t_ns\":300000000,\"slots\":[]}"));
  const std::string manifest = ReadTextFile(dir / "d/dataset.yaml");
  EXPECT_THAT(manifest, HasSubstr("format: \"parkslam-dataset\"\nversion: 2\n"));
  EXPECT_THAT(manifest, HasSubstr("\nvehicle:\n  wheelbase_m: 2.7\n  steering_ratio: 15\n"));
  EXPECT_THAT(manifest, HasSubstr("\nsensors:\n  odometry:\n    wheel_rate_hz: 50\n"));
  EXPECT_THAT(manifest, HasSubstr("counts:\n  wheel_speed: 3\n  steering: 2\n  imu: 2\n"));
  EXPECT_THAT(manifest, HasSubstr("duration_s: 0.3\n"));
  EXPECT_THAT(manifest, HasSubstr("\nscenario:\n  world:\n    name: \"test lot\"\n"));
}

TEST(DatasetTest, MissingDatasetYamlIsReported) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  std::filesystem::remove(dir / "d/dataset.yaml");
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }), HasSubstr("d/dataset.yaml: missing"));
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "nowhere"); }),
              HasSubstr("nowhere/dataset.yaml: missing"));
}

TEST(DatasetTest, NaNInCsvNamesFileLineAndField) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/sensors/imu.csv", "0,0.01,-3.14159", "0,0.01,nan");
  EXPECT_EQ(ErrorOf([&] { ReadDataset(dir / "d"); }),
            (dir / "d/sensors/imu.csv").string() + ":2: heading_rad: not a finite number");
}

TEST(DatasetTest, NonNumberInCsvIsReported) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/sensors/steering.csv", "-3.3", "-3.3x");
  EXPECT_EQ(
      ErrorOf([&] { ReadDataset(dir / "d"); }),
      (dir / "d/sensors/steering.csv").string() + ":3: steering_wheel_rad: not a number '-3.3x'");
}

TEST(DatasetTest, NonIncreasingTimestampsNameFileAndLine) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/sensors/wheel_speed.csv", "40000000,", "20000000,");
  EXPECT_EQ(ErrorOf([&] { ReadDataset(dir / "d"); }),
            (dir / "d/sensors/wheel_speed.csv").string() +
                ":4: t_ns: not strictly increasing (20000000 after 20000000)");
}

// A sample raised by 1e15 ns (still increasing) made odometry run without
// end; a gap over 10 s, or time below zero, is refused where it is read.
TEST(DatasetTest, LongGapsAndNegativeTimesAreRefused) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/sensors/wheel_speed.csv", "40000000,", "1000000000040000000,");
  EXPECT_EQ(ErrorOf([&] { ReadDataset(dir / "d"); }),
            (dir / "d/sensors/wheel_speed.csv").string() +
                ":4: t_ns: a gap of 1000000000020 ms after the previous sample (at most 10 s; "
                "split the recording there)");
  WriteDataset(dir / "e", SampleDataset());
  EditFile(dir / "e/sensors/wheel_speed.csv", "\n0,", "\n-5,");
  EXPECT_EQ(
      ErrorOf([&] { ReadDataset(dir / "e"); }),
      (dir / "e/sensors/wheel_speed.csv").string() + ":2: t_ns: below zero (time starts at 0)");
  // 10 s exactly is still a pause.
  WriteDataset(dir / "f", SampleDataset());
  EditFile(dir / "f/sensors/wheel_speed.csv", "40000000,", "10020000000,");
  EXPECT_EQ(ErrorOf([&] { ReadDataset(dir / "f"); }), "");
}

TEST(DatasetTest, ImplausibleSensorValuesAreRefused) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/sensors/imu.csv", "0,0.01,-3.14159", "0,0.01,1e308");
  EXPECT_EQ(ErrorOf([&] { ReadDataset(dir / "d"); }),
            (dir / "d/sensors/imu.csv").string() +
                ":2: heading_rad: 1e+308 is beyond the plausible 10000 rad");
  WriteDataset(dir / "e", SampleDataset());
  EditFile(dir / "e/sensors/steering.csv", "-3.3", "-300");
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "e"); }),
              HasSubstr("steering.csv:3: steering_wheel_rad: -300 is beyond the plausible 30 rad"));
}

TEST(DatasetTest, NonIncreasingFrameTimesAreReported) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/observations/tags.jsonl", "250000000", "100000000");
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }),
              HasSubstr("tags.jsonl:2: t_ns: not strictly increasing"));
}

TEST(DatasetTest, WrongCsvHeaderIsReported) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/sensors/wheel_speed.csv", "t_ns,speed_mps", "t_ns,speed");
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }),
              HasSubstr("wheel_speed.csv:1: expected the header 't_ns,speed_mps'"));
}

TEST(DatasetTest, WrongCsvFieldCountIsReported) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/sensors/imu.csv", "0,0.01,-3.14159", "0,0.01");
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }),
              HasSubstr("imu.csv:2: expected 3 fields, got 2"));
}

TEST(DatasetTest, AGyroOnlyImuLeavesTheHeadingEmpty) {
  const TempDir dir;
  Dataset dataset = SampleDataset();
  dataset.log.imu_samples[1].heading_rad.reset();
  WriteDataset(dir / "d", dataset);
  EXPECT_EQ(ReadTextFile(dir / "d/sensors/imu.csv"),
            "t_ns,yaw_rate_radps,heading_rad\n0,0.01,-3.14159\n"
            "10000000,0.30000000000000004,\n");
  const Dataset read = ReadDataset(dir / "d");
  EXPECT_EQ(read.log.imu_samples[0].heading_rad, -3.14159);
  EXPECT_FALSE(read.log.imu_samples[1].heading_rad.has_value());
  // Only the heading may be empty.
  EditFile(dir / "d/sensors/imu.csv", "0,0.01,-3.14159", "0,,-3.14159");
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }), HasSubstr("imu.csv:2: yaw_rate_radps"));
}

TEST(DatasetTest, TruncatedJsonLineIsReported) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  const std::filesystem::path file = dir / "d/observations/slots.jsonl";
  std::string content = ReadTextFile(file);
  content.resize(content.size() - 10);  // cut into the last line
  WriteFileAtomically(file, content);
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }),
              HasSubstr(file.string() + ":3: invalid JSON"));
}

TEST(DatasetTest, UnknownKeyInJsonLineNamesItsPath) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/observations/tags.jsonl", "\"yaw_sigma_rad\"", "\"yaw_sigma\"");
  EXPECT_EQ(ErrorOf([&] { ReadDataset(dir / "d"); }),
            (dir / "d/observations/tags.jsonl").string() + ":1: tags[0].yaw_sigma: unknown key");
}

TEST(DatasetTest, WrongTypeInJsonLineNamesItsPath) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/observations/slots.jsonl", "[\"8\",0.15]", "[8,0.15]");
  EXPECT_EQ(ErrorOf([&] { ReadDataset(dir / "d"); }),
            (dir / "d/observations/slots.jsonl").string() +
                ":1: slots[0].id[0][1][0]: expected a string, got an integer");
}

// The message of reading the sample dataset with the first `from` in `file`
// replaced by `to`.
std::string ErrorReadingEdited(const std::string& file, const std::string& from,
                               const std::string& to) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d" / file, from, to);
  return ErrorOf([&] { ReadDataset(dir / "d"); });
}

// nlohmann refuses a number beyond the range of a double with out_of_range,
// not parse_error, and names no position: every JSON file of a dataset must
// still fail with an IoError naming the file, the line and the field.
TEST(DatasetTest, NumberTooLargeForADoubleInJsonNamesFileLineAndField) {
  const std::string sigma =
      ErrorReadingEdited("observations/slots.jsonl", "\"sigma_m\":0.031", "\"sigma_m\":1e999");
  EXPECT_THAT(sigma, HasSubstr("observations/slots.jsonl:1: slots[0].sigma_m: invalid JSON: "));
  EXPECT_THAT(sigma, HasSubstr("1e999"));
  EXPECT_THAT(ErrorReadingEdited("observations/slots.jsonl", "[\"8\",0.15]", "[\"8\",-1e999]"),
              HasSubstr("observations/slots.jsonl:1: slots[0].id[0][1][1]: invalid JSON: "));
  EXPECT_THAT(ErrorReadingEdited("observations/tags.jsonl", "\"yaw_sigma_rad\":0.03",
                                 "\"yaw_sigma_rad\":1e999"),
              HasSubstr("observations/tags.jsonl:1: tags[0].yaw_sigma_rad: invalid JSON: "));
  EXPECT_THAT(ErrorReadingEdited("observations/tags.jsonl", "250000000", "1e999"),
              HasSubstr("observations/tags.jsonl:2: t_ns: invalid JSON: "));
  EXPECT_THAT(
      ErrorReadingEdited("groundtruth/slot_labels.jsonl", "\"slots\":[2]", "\"slots\":[1e999]"),
      HasSubstr("groundtruth/slot_labels.jsonl:2: slots[0]: invalid JSON: "));
  EXPECT_THAT(ErrorReadingEdited("groundtruth/map.json", "5.3]", "1e999]"),
              HasSubstr("groundtruth/map.json: slots[0].corners[2][1]: invalid JSON: "));
}

// Observations beyond the limits of common/plausible_ranges.h, each named
// by file, line and JSON path.
TEST(DatasetTest, ImplausibleObservationsAreRefused) {
  const std::string slots = "observations/slots.jsonl";
  const std::string tags = "observations/tags.jsonl";
  EXPECT_THAT(
      ErrorReadingEdited(slots, "[[1,1.5]", "[[1e308,1.5]"),
      HasSubstr(slots + ":1: slots[0].corners[0][0]: 1e+308 is beyond the plausible 100 m"));
  EXPECT_THAT(ErrorReadingEdited(slots, "[0.5,1.5]", "[0.5,-150]"),
              HasSubstr(slots + ":2: slots[0].corners[0][1]: -150 is beyond the plausible 100 m"));
  EXPECT_THAT(
      ErrorReadingEdited(slots, "\"sigma_m\":0.031", "\"sigma_m\":50"),
      HasSubstr(slots + ":1: slots[0].sigma_m: 50 is outside the plausible range [0, 10] m"));
  EXPECT_THAT(ErrorReadingEdited(tags, "\"x_m\":5.1", "\"x_m\":1e6"),
              HasSubstr(tags + ":1: tags[0].x_m: 1e+06 is beyond the plausible 100 m"));
  EXPECT_THAT(ErrorReadingEdited(tags, "\"y_m\":-0.4", "\"y_m\":-101"),
              HasSubstr(tags + ":1: tags[0].y_m: -101 is beyond the plausible 100 m"));
  const std::string range = ErrorReadingEdited(tags, "\"range_m\":3.", "\"range_m\":-5003.");
  EXPECT_THAT(range, HasSubstr(tags + ":1: tags[0].range_m: -5003."));
  EXPECT_THAT(range, HasSubstr(" is beyond the plausible 100 m"));
  EXPECT_THAT(
      ErrorReadingEdited(tags, "\"bearing_rad\":-0.1234567890123", "\"bearing_rad\":-1e5"),
      HasSubstr(tags + ":1: tags[0].bearing_rad: -1e+05 is beyond the plausible 10000 rad"));
  EXPECT_THAT(ErrorReadingEdited(tags, "\"yaw_rad\":3,", "\"yaw_rad\":1e300,"),
              HasSubstr(tags + ":1: tags[0].yaw_rad: 1e+300 is beyond the plausible 10000 rad"));
  EXPECT_THAT(ErrorReadingEdited(tags, "[4e-04,-1e-04,9e-04]", "[-4e-04,-1e-04,9e-04]"),
              HasSubstr(tags + ":1: tags[0].cov[0]: -4e-04 is outside the plausible range "
                               "[0, 100] m^2"));
  EXPECT_THAT(ErrorReadingEdited(tags, "[4e-04,-1e-04,9e-04]", "[4e-04,-1e-04,1e9]"),
              HasSubstr(tags + ":1: tags[0].cov[2]: 1e+09 is outside the plausible range "
                               "[0, 100] m^2"));
  EXPECT_THAT(ErrorReadingEdited(tags, "[4e-04,-1e-04,9e-04]", "[4e-04,-0.01,9e-04]"),
              HasSubstr(tags + ":1: tags[0].cov: not a covariance: xy^2 exceeds xx yy"));
  EXPECT_THAT(ErrorReadingEdited(tags, "\"yaw_sigma_rad\":0.03", "\"yaw_sigma_rad\":4"),
              HasSubstr(tags + ":1: tags[0].yaw_sigma_rad: 4 is outside the plausible range [0, "
                               "3.14159] rad"));
  // Issue: "observations with an ID digit x, tag id -1, zero-area slots".
  EXPECT_THAT(ErrorReadingEdited(slots, "[\"3\",0.8]", "[\"x\",0.8]"),
              HasSubstr(slots + ":1: slots[0].id[0][0][0]: expected one digit 0-9, got 'x'"));
  // An independent probe: an ID of 100 unread digits, and one digit's readings
  // adding up to 2.7.
  std::string hundred = "[[]";
  for (int d = 1; d < 100; ++d) hundred += ",[]";
  hundred += "]";
  EXPECT_THAT(ErrorReadingEdited(slots, "[[[\"3\",0.8],[\"8\",0.15]],[[\"9\",0.9]]]", hundred),
              HasSubstr(slots + ":1: slots[0].id: 100 digits; a painted ID has at most 8"));
  EXPECT_THAT(ErrorReadingEdited(slots, "[\"8\",0.15]", "[\"8\",0.9]"),
              HasSubstr(slots + ":1: slots[0].id[0]: its probabilities add up to 1.700000"));
  EXPECT_THAT(ErrorReadingEdited(tags, "\"id\":7,", "\"id\":-1,"),
              HasSubstr(tags + ":1: tags[0].id: must be a tag36h11 ID in [0, 586], got -1"));
  EXPECT_THAT(ErrorReadingEdited(tags, "\"id\":7,", "\"id\":587,"),
              HasSubstr(tags + ":1: tags[0].id: must be a tag36h11 ID in [0, 586], got 587"));
  EXPECT_THAT(ErrorReadingEdited(slots, "[3.5,6.8],[1,6.8]", "[3.5,1.5],[1,1.5]"),
              HasSubstr(slots + ":1: slots[0].corners: the corners enclose 0.00 m^2, not a slot"));
  // Crossed over (a bow tie): distinct corners, no area.
  EXPECT_THAT(ErrorReadingEdited(slots, "[3.5,6.8],[1,6.8]", "[1,6.8],[3.5,6.8]"),
              HasSubstr(slots + ":1: slots[0].corners: the corners enclose 0.00 m^2, not a slot"));
  // A noise-free simulation's covariance is zero, and a single noisy
  // direction's singular: both are covariances.
  EXPECT_EQ(ErrorReadingEdited(tags, "[4e-04,-1e-04,9e-04]", "[0,0,0]"), "");
  EXPECT_EQ(ErrorReadingEdited(tags, "[4e-04,-1e-04,9e-04]", "[4e-04,-6e-04,9e-04]"), "");
}

// A recording from a real car: the vehicle and the sensors' datasheet, no
// scenario.
TEST(DatasetTest, ADatasetWithoutScenarioRoundTrips) {
  const TempDir dir;
  Dataset d = SampleDataset();
  d.scenario.reset();
  d.vehicle.wheelbase_m = 2.85;
  d.odometry_spec.gyro_sigma_radps = 0.002;
  WriteDataset(dir / "d", d);
  const std::string manifest = ReadTextFile(dir / "d/dataset.yaml");
  EXPECT_THAT(manifest, Not(HasSubstr("scenario")));
  const Dataset back = ReadDataset(dir / "d");
  ExpectDatasetsEqual(d, back);
  EXPECT_EQ(back.vehicle.wheelbase_m, 2.85);
  EXPECT_FALSE(back.scenario.has_value());
}

TEST(DatasetTest, EveryVehicleAndSensorFieldIsRequired) {
  const TempDir dir;
  Dataset d = SampleDataset();
  d.scenario.reset();
  WriteDataset(dir / "d", d);
  EditFile(dir / "d/dataset.yaml", "  steering_ratio: 15\n", "");
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }),
              HasSubstr("vehicle.steering_ratio: missing key"));
  WriteDataset(dir / "d", d);
  EditFile(dir / "d/dataset.yaml", "    imu_rate_hz: 100\n", "    imu_rate_hz: 0\n");
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }),
              HasSubstr("sensors.odometry.imu_rate_hz: must be in [1, 1000] Hz"));
}

TEST(DatasetTest, AScenarioOfAnotherCarIsRefused) {
  const TempDir dir;
  Dataset d = SampleDataset();
  d.vehicle.wheelbase_m = 3.1;  // the scenario still says 2.7
  WriteDataset(dir / "d", d);
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }),
              HasSubstr("scenario.vehicle: differs from the vehicle section"));
}

// Version 1 kept the vehicle and the sensors only in the scenario.
TEST(DatasetTest, VersionOneIsStillRead) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  std::string manifest = ReadTextFile(dir / "d/dataset.yaml");
  const std::size_t vehicle = manifest.find("\nvehicle:\n");
  const std::size_t scenario = manifest.find("\nscenario:\n");
  ASSERT_NE(vehicle, std::string::npos);
  ASSERT_NE(scenario, std::string::npos);
  manifest.erase(vehicle, scenario - vehicle);
  manifest.replace(manifest.find("version: 2"), 10, "version: 1");
  WriteFileAtomically(dir / "d/dataset.yaml", manifest);
  const Dataset back = ReadDataset(dir / "d");
  ASSERT_TRUE(back.scenario.has_value());
  EXPECT_EQ(back.vehicle.wheelbase_m, back.scenario->vehicle.wheelbase_m);
  EXPECT_EQ(back.odometry_spec.imu_rate_hz, 100.0);
}

// The commands take the vehicle and the sensor noise from dataset.yaml, and
// an embedded scenario must be valid.
TEST(DatasetTest, ImplausibleScenarioInDatasetYamlIsRefused) {
  const std::string error = ErrorReadingEdited("dataset.yaml", "max_x_m: 87.5", "max_x_m: 1e9");
  EXPECT_THAT(error, HasSubstr("dataset.yaml:"));
  EXPECT_THAT(error, HasSubstr(": scenario.world.hall: must be at most 100000 m in magnitude"));
}

TEST(DatasetTest, UnknownTopLevelKeyInDatasetYamlIsRejected) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/dataset.yaml", "counts:", "colour: red\ncounts:");
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }),
              HasSubstr("dataset.yaml:9: colour: unknown key"));
}

TEST(DatasetTest, UnknownKeyInEmbeddedScenarioNamesItsPath) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/dataset.yaml", "    laps: 1\n", "    lap: 1\n");
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }),
              HasSubstr("scenario.route.lap: unknown key (did you mean 'laps'?)"));
}

TEST(DatasetTest, WrongFormatIsRejected) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/dataset.yaml", "version: 2", "version: 3");
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }),
              HasSubstr("version: unsupported version 3"));
}

TEST(DatasetTest, FileShorterThanAnnouncedIsReported) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/sensors/imu.csv", "10000000,0.30000000000000004,3.1\n", "");
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }),
              HasSubstr("counts.imu: announces 2, but sensors/imu.csv has 1"));
}

TEST(DatasetTest, LabelsNotMatchingSlotFramesAreReported) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/groundtruth/slot_labels.jsonl", "\"slots\":[2]", "\"slots\":[2,1]");
  EXPECT_EQ(ErrorOf([&] { ReadDataset(dir / "d"); }),
            (dir / "d/groundtruth/slot_labels.jsonl").string() +
                ":2: slots: 2 labels for 1 observations");
}

TEST(DatasetTest, LabelBeyondTheMapIsReported) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/groundtruth/slot_labels.jsonl", "\"slots\":[2]", "\"slots\":[3]");
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }),
              HasSubstr("slot_labels.jsonl:2: slots[0]: label 3 out of range "
                        "(groundtruth/map.json has 3 slots)"));
}

TEST(DatasetTest, MissingSensorFileIsReported) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  std::filesystem::remove(dir / "d/sensors/steering.csv");
  EXPECT_THAT(ErrorOf([&] { ReadDataset(dir / "d"); }), HasSubstr("sensors/steering.csv"));
}

TEST(DatasetTest, WritingRefusesNaNAndLeavesNoManifest) {
  const TempDir dir;
  Dataset dataset = SampleDataset();
  dataset.log.tag_frames[0].tags[1].range_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(ErrorOf([&] { WriteDataset(dir / "d", dataset); }),
              HasSubstr("tags.jsonl: tags[1].range_m: not a finite number (entry 0"));
  EXPECT_FALSE(std::filesystem::exists(dir / "d/dataset.yaml"));
}

TEST(DatasetTest, WritingRefusesUnsortedSamples) {
  const TempDir dir;
  Dataset dataset = SampleDataset();
  std::swap(dataset.log.imu_samples[0], dataset.log.imu_samples[1]);
  EXPECT_THAT(ErrorOf([&] { WriteDataset(dir / "d", dataset); }),
              HasSubstr("imu.csv: t_ns: not strictly increasing"));
}

TEST(DatasetTest, WritingRefusesLabelsThatDoNotMatch) {
  const TempDir dir;
  Dataset dataset = SampleDataset();
  dataset.slot_labels.pop_back();
  EXPECT_THAT(ErrorOf([&] { WriteDataset(dir / "d", dataset); }),
              HasSubstr("2 label frames for 3 slot frames"));
}

// A 10-minute drive: 30k wheel, 30k steering, 60k IMU samples, 6000 slot and
// tag frames, 60k ground-truth poses.
Dataset LargeDataset() {
  Dataset d = SampleDataset();
  d.log = {};
  d.groundtruth_trajectory.clear();
  d.slot_labels.clear();
  constexpr TimeNs kMs = 1'000'000;
  for (TimeNs t = 0; t < 600'000 * kMs; t += 20 * kMs) {
    const double s = static_cast<double>(t) * 1e-9;
    d.log.wheel_speeds.push_back({t, 2.5 + 0.1 * std::sin(s)});
    d.log.steering_angles.push_back({t + kMs, 0.3 * std::cos(0.1 * s)});
  }
  for (TimeNs t = 0; t < 600'000 * kMs; t += 10 * kMs) {
    const double s = static_cast<double>(t) * 1e-9;
    d.log.imu_samples.push_back({t, 0.01 * std::sin(s), NormalizeAngle(0.05 * s)});
    d.groundtruth_trajectory.push_back({t, SE2(0.1 * s, std::sin(s), 0.05 * s)});
  }
  const SlotIdReading id{{Digit({{'3', 0.8}, {'8', 0.15}}), Digit({{'9', 0.9}})}};
  for (TimeNs t = 0; t < 600'000 * kMs; t += 100 * kMs) {
    d.log.slot_frames.push_back({t, {Slot(1.0, id), Slot(3.5, SlotIdReading{})}});
    d.log.tag_frames.push_back({t + kMs, {Tag(3, 4.0)}});
    d.slot_labels.push_back({0, 1});
  }
  return d;
}

// A ten-minute drive round-trips whole. Its speed is measured by
// bench/io_bench.cc, not here: timed tests are flaky on shared machines.
TEST(DatasetTest, TenMinuteDriveRoundTrips) {
  const TempDir dir;
  const Dataset dataset = LargeDataset();
  WriteDataset(dir / "d", dataset);
  const Dataset read = ReadDataset(dir / "d");
  ASSERT_EQ(read.log.imu_samples.size(), 60'000u);
  EXPECT_EQ(read.log.imu_samples.back().heading_rad, dataset.log.imu_samples.back().heading_rad);
  EXPECT_EQ(read.log.wheel_speeds[12345].speed_mps, dataset.log.wheel_speeds[12345].speed_mps);
  EXPECT_EQ(read.slot_labels.size(), 6'000u);
}

}  // namespace
}  // namespace parkslam::io

namespace parkslam::io {
namespace {

TEST(CheckDatasetTest, AGoodDatasetHasNoProblemAndItsStreamsSummarized) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  const DatasetCheck check = CheckDataset(dir / "d");
  EXPECT_TRUE(check.ok()) << (check.errors.empty() ? "" : check.errors.front());
  ASSERT_EQ(check.streams.size(), 5u);
  EXPECT_EQ(check.streams[0].name, "sensors/wheel_speed.csv");
  EXPECT_EQ(check.streams[0].count, 3u);
  EXPECT_DOUBLE_EQ(check.streams[0].median_period_s, 0.02);
  EXPECT_DOUBLE_EQ(check.streams[3].last_s, 0.3);  // slot frames
}

// The readers stop at the first problem; the check lists them all.
TEST(CheckDatasetTest, EveryProblemIsListedWithItsFile) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/sensors/imu.csv", "0,0.01,-3.14159", "0,0.01,nan");
  std::filesystem::remove(dir / "d/sensors/steering.csv");
  EditFile(dir / "d/sensors/wheel_speed.csv", "40000000,", "1540000000,");
  const DatasetCheck check = CheckDataset(dir / "d");
  ASSERT_EQ(check.errors.size(), 3u);
  EXPECT_THAT(check.errors[0], HasSubstr("steering.csv"));
  EXPECT_THAT(check.errors[1], HasSubstr("imu.csv:2: heading_rad: not a finite number"));
  EXPECT_THAT(check.errors[2],
              HasSubstr("wheel_speed.csv: a gap of 1.52 s after t = 0.020 s (more than 1.00 s)"));
  // A longer limit lets the gap pass.
  EXPECT_EQ(CheckDataset(dir / "d", 2.0).errors.size(), 2u);
}

// Issue: "check-dataset says ok to a NaN or reversed ground-truth
// trajectory, a truncated map.json, an IMU running an hour past the other
// streams": what the eval commands would refuse, the check lists.
TEST(CheckDatasetTest, GroundTruthIsCheckedAsTheEvalCommandsReadIt) {
  const auto problems = [](const std::string& file, const std::string& from,
                           const std::string& to) {
    const TempDir dir;
    WriteDataset(dir / "d", SampleDataset());
    EXPECT_TRUE(CheckDataset(dir / "d").ok());
    if (to == "<cut>") {
      const std::string text = ReadTextFile(dir / "d" / file);
      WriteFileAtomically(dir / "d" / file, text.substr(0, text.find(from)));
    } else {
      EditFile(dir / "d" / file, from, to);
    }
    std::string all;
    for (const std::string& e : CheckDataset(dir / "d").errors) all += e + "\n";
    return all;
  };
  EXPECT_THAT(problems("groundtruth/trajectory.tum", "-37.000000", "nan"),
              HasSubstr("groundtruth/trajectory.tum:2: x: not a finite number"));
  // Reversed: the second pose before the first.
  EXPECT_THAT(problems("groundtruth/trajectory.tum", "\n0.010000000 ", "\n-0.010000000 "),
              HasSubstr("groundtruth/trajectory.tum:3: t: not strictly increasing"));
  EXPECT_THAT(problems("groundtruth/map.json", "\"tags\"", "<cut>"),
              HasSubstr("groundtruth/map.json: invalid JSON: "));
  EXPECT_THAT(
      problems("groundtruth/slot_labels.jsonl", "\n", "\n{\"t_ns\":150000000,\"slots\":[]}\n"),
      HasSubstr("groundtruth/slot_labels.jsonl:2: t_ns: 150000000 does not match slot "
                "frame 1"));
}

TEST(CheckDatasetTest, StreamsOfOneDriveEndTogether) {
  const TempDir dir;
  Dataset d = SampleDataset();
  // An IMU running on for an hour after the other streams, at its rate.
  const TimeNs last = d.log.imu_samples.back().t_ns;
  for (TimeNs k = 1; k <= 3600 * 10; ++k) {
    d.log.imu_samples.push_back({last + k * 100'000'000, 0.0, std::nullopt});
  }
  WriteDataset(dir / "d", d);
  const DatasetCheck check = CheckDataset(dir / "d");
  ASSERT_EQ(check.errors.size(), 1u);
  EXPECT_THAT(check.errors[0],
              HasSubstr("sensors/imu.csv: runs from 0.000 s to 3600.010 s, but the other streams "
                        "from about 0.000 s to 0.250 s (the streams of one drive start and end "
                        "within 60 s of each other)"));
}

TEST(CheckDatasetTest, CountsAgainstTheManifestAndAMissingFolder) {
  const TempDir dir;
  WriteDataset(dir / "d", SampleDataset());
  EditFile(dir / "d/dataset.yaml", "wheel_speed: 3", "wheel_speed: 4");
  const DatasetCheck check = CheckDataset(dir / "d");
  ASSERT_EQ(check.errors.size(), 1u);
  EXPECT_THAT(check.errors[0], HasSubstr("4 announced for sensors/wheel_speed.csv, which holds 3"));
  EXPECT_THAT(CheckDataset(dir / "nowhere").errors.at(0), HasSubstr("not a folder"));
}

}  // namespace
}  // namespace parkslam::io
