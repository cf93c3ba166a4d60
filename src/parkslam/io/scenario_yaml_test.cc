#include "parkslam/io/scenario_yaml.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include "parkslam/io/io_error.h"
#include "parkslam/io/test_util.h"

namespace parkslam::io {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;

struct NoOp {
  template <typename T>
  void operator()(const char*, T&) {}
};
template <typename T>
concept HasFields = requires(T& t, NoOp& v) {
  t.VisitFields(v);
};

using Leaves = std::vector<std::pair<std::string, std::string>>;

// Every leaf field as (dotted path, exact text), walked through the structs'
// own field lists, independently of the YAML code under test.
class Flattener {
 public:
  Flattener(std::string prefix, Leaves* leaves) : prefix_(std::move(prefix)), leaves_(leaves) {}

  template <typename T>
  void operator()(const char* key, T& field) {
    Add(prefix_.empty() ? key : prefix_ + "." + key, field);
  }

 private:
  void Add(const std::string& path, double v) {
    std::ostringstream s;
    s << std::hexfloat << v;
    leaves_->push_back({path, s.str()});
  }
  void Add(const std::string& path, int v) { leaves_->push_back({path, std::to_string(v)}); }
  void Add(const std::string& path, bool v) { leaves_->push_back({path, v ? "T" : "F"}); }
  void Add(const std::string& path, const std::string& v) { leaves_->push_back({path, v}); }
  void Add(const std::string& path, const Eigen::Vector2d& v) {
    Add(path + ".x", v.x());
    Add(path + ".y", v.y());
  }
  template <typename T>
  void Add(const std::string& path, std::vector<T>& v) {
    leaves_->push_back({path + ".size", std::to_string(v.size())});
    for (std::size_t i = 0; i < v.size(); ++i) Add(path + "[" + std::to_string(i) + "]", v[i]);
  }
  template <typename T>
  void Add(const std::string& path, std::optional<T>& v) {
    leaves_->push_back({path + ".set", v ? "T" : "F"});
    if (v) Add(path, *v);
  }
  template <HasFields T>
  void Add(const std::string& path, T& v) {
    Flattener inner(path, leaves_);
    v.VisitFields(inner);
  }

  std::string prefix_;
  Leaves* leaves_;
};

Leaves Flatten(sim::ScenarioConfig config) {
  Leaves leaves;
  Flattener flattener("", &leaves);
  config.VisitFields(flattener);
  return leaves;
}

// Changes every field of a configuration.
class Mutator {
 public:
  template <typename T>
  void operator()(const char*, T& field) {
    Change(field);
  }

 private:
  void Change(double& v) { v = -v + 1.5; }
  void Change(int& v) { v += 7; }
  void Change(bool& v) { v = !v; }
  void Change(std::string& v) { v += "_changed"; }
  void Change(Eigen::Vector2d& v) { v += Eigen::Vector2d(0.5, -0.25); }
  template <typename T>
  void Change(std::vector<T>& v) {
    v.emplace_back();
    for (T& element : v) Change(element);
  }
  template <typename T>
  void Change(std::optional<T>& v) {
    if (v) Change(*v);
  }
  template <HasFields T>
  void Change(T& v) {
    v.VisitFields(*this);
  }
};

sim::ScenarioConfig Mutated(sim::ScenarioConfig config) {
  Mutator mutator;
  config.VisitFields(mutator);
  return config;
}

TEST(ScenarioYamlTest, DefaultScenarioRoundTripsFieldForField) {
  const sim::ScenarioConfig original = sim::DefaultScenario();
  const sim::ScenarioConfig other = Mutated(original);
  const sim::ScenarioConfig read =
      ScenarioFromYaml(ScenarioToYaml(original), other, "round_trip.yaml");
  const Leaves expected = Flatten(original);
  const Leaves got = Flatten(read);
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], expected[i]);
  EXPECT_GT(expected.size(), 150u);
}

TEST(ScenarioYamlTest, RoundTripKeepsAwkwardValuesExactly) {
  sim::ScenarioConfig original = sim::DefaultScenario();
  original.world.name =
      "Parkhaus S\xc3\xbc"
      "d: \"B2\" # level -2\\";
  original.world.id_worn_rate = 0.1 + 0.2;
  original.world.rows[0].origin_m = Eigen::Vector2d(1e-300, -123456.789e10);
  original.route.finish_m.clear();
  original.world.tag_regions.clear();
  original.sensors.ids.confusion_rate = 1.0 / 3.0;
  const sim::ScenarioConfig read =
      ScenarioFromYaml(ScenarioToYaml(original), Mutated(original), "awkward.yaml");
  EXPECT_EQ(Flatten(read), Flatten(original));
  EXPECT_EQ(read.world.name, original.world.name);
  EXPECT_EQ(read.world.id_worn_rate, 0.1 + 0.2);
  EXPECT_TRUE(read.route.finish_m.empty());
}

TEST(ScenarioYamlTest, WritesReadableBlockYaml) {
  sim::ScenarioConfig config = sim::DefaultScenario();
  config.world.name = "lot";
  config.world.hall = {0.0, 0.0, 82.0, 50.5};
  config.world.rows.resize(1);
  config.world.rows[0].origin_m = Eigen::Vector2d(8.0, 5.6);
  config.route.approach_m = {{-37.0, 9.1}, {-10.0, 9.1}};
  config.sensors.ids.confusion_rate = 0.05;
  config.sensors.odometry.gyro_bias_walk_radps_per_sqrt_s = 5e-5;
  const std::string yaml = ScenarioToYaml(config);
  EXPECT_THAT(yaml, HasSubstr("\nworld:\n  name: \"lot\"\n"));
  EXPECT_THAT(yaml, HasSubstr("\n  hall: {min_x_m: 0, min_y_m: 0, max_x_m: 82, max_y_m: 50.5}\n"));
  EXPECT_THAT(yaml,
              HasSubstr("\n  rows:\n    - kind: \"perpendicular\"\n      origin_m: [8, 5.6]\n"));
  EXPECT_THAT(yaml, HasSubstr("\n  approach_m: [[-37, 9.1], [-10, 9.1]]\n"));
  EXPECT_THAT(yaml, HasSubstr("\n    confusion_rate: 0.05\n"));
  EXPECT_THAT(yaml, HasSubstr("\n    gyro_bias_walk_radps_per_sqrt_s: 5.0e-05\n"));
}

TEST(ScenarioYamlTest, OverlayKeepsUnspecifiedFields) {
  const sim::ScenarioConfig base = sim::DefaultScenario();
  const sim::ScenarioConfig read = ScenarioFromYaml(
      "route:\n  laps: 5\nsensors:\n  ids:\n    confusion_rate: 0.2\n", base, "o.yaml");
  EXPECT_EQ(read.route.laps, 5);
  EXPECT_EQ(read.sensors.ids.confusion_rate, 0.2);
  sim::ScenarioConfig expected = base;
  expected.route.laps = 5;
  expected.sensors.ids.confusion_rate = 0.2;
  EXPECT_EQ(Flatten(read), Flatten(expected));
}

TEST(ScenarioYamlTest, EmptyTextChangesNothing) {
  const sim::ScenarioConfig base = sim::DefaultScenario();
  EXPECT_EQ(Flatten(ScenarioFromYaml("# nothing\n", base, "e.yaml")), Flatten(base));
}

TEST(ScenarioYamlTest, AListReplacesTheBaseListWholeFromDefaults) {
  const sim::ScenarioConfig base = sim::DefaultScenario();
  ASSERT_GE(base.world.rows.size(), 2u);
  ASSERT_NE(base.world.rows[0].origin_m, Eigen::Vector2d(0.0, 0.0));
  const sim::ScenarioConfig read =
      ScenarioFromYaml("world:\n  rows:\n    - count: 3\n      first_id: 50\n", base, "r.yaml");
  ASSERT_EQ(read.world.rows.size(), 1u);
  EXPECT_EQ(read.world.rows[0].count, 3);
  EXPECT_EQ(read.world.rows[0].first_id, 50);
  // Not base.world.rows[0].origin_m: the struct's default.
  EXPECT_EQ(read.world.rows[0].origin_m, Eigen::Vector2d(0.0, 0.0));
  EXPECT_EQ(read.world.tag_regions.size(), base.world.tag_regions.size());
}

TEST(ScenarioYamlTest, UnknownKeyNamesFileLineAndKeyPath) {
  const std::string yaml =
      "world:\n"
      "  rows:\n"
      "    - count: 3\n"
      "    - count: 4\n"
      "    - count: 5\n"
      "      widht_m: 2.6\n";
  EXPECT_EQ(ErrorOf([&] { ScenarioFromYaml(yaml, sim::DefaultScenario(), "world.yaml"); }),
            "world.yaml:6: world.rows[2].widht_m: unknown key (did you mean 'width_m'?)");
}

TEST(ScenarioYamlTest, UnknownTopLevelKeyIsRejected) {
  EXPECT_EQ(ErrorOf([] { ScenarioFromYaml("wrold: {}\n", sim::DefaultScenario(), "w.yaml"); }),
            "w.yaml:1: wrold: unknown key (did you mean 'world'?)");
}

TEST(ScenarioYamlTest, WrongTypeNamesTheKeyPath) {
  EXPECT_EQ(
      ErrorOf([] { ScenarioFromYaml("route:\n  laps: two\n", sim::DefaultScenario(), "w.yaml"); }),
      "w.yaml:2: route.laps: expected an integer, got 'two'");
  EXPECT_EQ(ErrorOf([] {
              ScenarioFromYaml("vehicle:\n  wheelbase_m: long\n", sim::DefaultScenario(), "w.yaml");
            }),
            "w.yaml:2: vehicle.wheelbase_m: expected a number, got 'long'");
  EXPECT_EQ(
      ErrorOf([] { ScenarioFromYaml("world:\n  hall: 5\n", sim::DefaultScenario(), "w.yaml"); }),
      "w.yaml:2: world.hall: expected a mapping of keys, got '5'");
  EXPECT_EQ(ErrorOf([] {
              ScenarioFromYaml("route:\n  loop_m: [[1, 2], [3]]\n", sim::DefaultScenario(),
                               "w.yaml");
            }),
            "w.yaml:2: route.loop_m[1]: expected a point [x, y], got a list");
}

TEST(ScenarioYamlTest, RejectsNonFiniteNumbersAndBadBooleans) {
  EXPECT_EQ(ErrorOf([] {
              ScenarioFromYaml("world:\n  pillar_size_m: .nan\n", sim::DefaultScenario(), "w.yaml");
            }),
            "w.yaml:2: world.pillar_size_m: not a finite number");
  EXPECT_EQ(ErrorOf([] {
              ScenarioFromYaml("world:\n  corridor: maybe\n", sim::DefaultScenario(), "w.yaml");
            }),
            "w.yaml:2: world.corridor: expected true or false, got 'maybe'");
}

TEST(ScenarioYamlTest, RejectsAKeyGivenTwice) {
  EXPECT_THAT(ErrorOf([] {
                ScenarioFromYaml("route:\n  laps: 1\n  laps: 2\n", sim::DefaultScenario(),
                                 "w.yaml");
              }),
              HasSubstr("route.laps: key given twice"));
}

TEST(ScenarioYamlTest, InvalidYamlSyntaxNamesTheFile) {
  EXPECT_THAT(
      ErrorOf([] { ScenarioFromYaml("world: [1, 2\n", sim::DefaultScenario(), "bad.yaml"); }),
      HasSubstr("bad.yaml:"));
}

TEST(ScenarioYamlTest, ApplyOverrideSetsNumbersStructsListsAndStrings) {
  const sim::ScenarioConfig base = sim::DefaultScenario();
  ASSERT_GE(base.world.rows.size(), 2u);
  sim::ScenarioConfig config = base;
  ApplyOverride(&config, "sensors.ids.confusion_rate=0.1");
  ApplyOverride(&config, "route.laps = 3");
  ApplyOverride(&config, "world.hall={min_x_m: 0, min_y_m: 0, max_x_m: 40, max_y_m: 30}");
  ApplyOverride(&config, "world.rows[1].count=12");
  ApplyOverride(&config, "route.loop_m=[[4, 9.5], [70, 9.5]]");
  ApplyOverride(&config, "world.name=small lot");
  ApplyOverride(&config, "world.corridor=false");
  EXPECT_EQ(config.sensors.ids.confusion_rate, 0.1);
  EXPECT_EQ(config.route.laps, 3);
  EXPECT_EQ(config.world.hall.max_x_m, 40.0);
  EXPECT_EQ(config.world.hall.max_y_m, 30.0);
  EXPECT_EQ(config.world.rows[1].count, 12);
  EXPECT_EQ(config.world.rows[0].count, base.world.rows[0].count);
  ASSERT_EQ(config.route.loop_m.size(), 2u);
  EXPECT_EQ(config.route.loop_m[1], Eigen::Vector2d(70.0, 9.5));
  EXPECT_EQ(config.world.name, "small lot");
  EXPECT_FALSE(config.world.corridor);
}

TEST(ScenarioYamlTest, ApplyOverrideOfAStructKeepsItsOtherFields) {
  const sim::ScenarioConfig base = sim::DefaultScenario();
  sim::ScenarioConfig config = base;
  ApplyOverride(&config, "world.hall={max_x_m: 60}");
  EXPECT_EQ(config.world.hall.max_x_m, 60.0);
  EXPECT_EQ(config.world.hall.min_x_m, base.world.hall.min_x_m);
  EXPECT_EQ(config.world.hall.max_y_m, base.world.hall.max_y_m);
}

TEST(ScenarioYamlTest, ApplyOverrideRejectsAnUnknownKey) {
  sim::ScenarioConfig config = sim::DefaultScenario();
  EXPECT_EQ(ErrorOf([&] { ApplyOverride(&config, "sensors.ids.foo=1"); }),
            "--set: unknown key 'sensors.ids.foo'");
  EXPECT_EQ(ErrorOf([&] { ApplyOverride(&config, "route.laps.x=1"); }),
            "--set: unknown key 'route.laps.x'");
  EXPECT_EQ(ErrorOf([&] { ApplyOverride(&config, "world..name=x"); }),
            "--set: unknown key 'world..name'");
  EXPECT_EQ(Flatten(config), Flatten(sim::DefaultScenario()));
}

TEST(ScenarioYamlTest, ApplyOverrideRejectsABadValueNamingTheKey) {
  sim::ScenarioConfig config = sim::DefaultScenario();
  EXPECT_EQ(ErrorOf([&] { ApplyOverride(&config, "route.laps=abc"); }),
            "--set: route.laps: expected an integer, got 'abc'");
  EXPECT_EQ(ErrorOf([&] { ApplyOverride(&config, "world.hall={max_x_m: wide}"); }),
            "--set: world.hall.max_x_m: expected a number, got 'wide'");
  EXPECT_EQ(ErrorOf([&] { ApplyOverride(&config, "route.laps"); }),
            "--set: expected key=value, got 'route.laps'");
  EXPECT_THAT(ErrorOf([&] { ApplyOverride(&config, "world.rows[9].count=1"); }),
              HasSubstr("--set: world.rows[9]: index out of range"));
  EXPECT_EQ(Flatten(config), Flatten(sim::DefaultScenario()));
}

TEST(ScenarioYamlTest, LoadScenarioFileOverlaysTheDefaultScenario) {
  const TempDir dir;
  const auto file = dir.Write("s.yaml", "route:\n  laps: 4\n");
  const sim::ScenarioConfig config = LoadScenarioFile(file);
  EXPECT_EQ(config.route.laps, 4);
  EXPECT_EQ(config.world.rows.size(), sim::DefaultScenario().world.rows.size());
}

TEST(ScenarioYamlTest, LoadScenarioFileRejectsAnInvalidScenario) {
  const TempDir dir;
  const auto file = dir.Write("invalid.yaml", "world:\n  rows:\n    - count: 0\n");
  // The validator's message, prefixed with the file.
  EXPECT_THAT(ErrorOf([&] { LoadScenarioFile(file); }),
              HasSubstr(file.string() + ": world.rows[0].count: "));
}

// Physical quantities beyond the limits of common/plausible_ranges.h, each
// named by file and field.
TEST(ScenarioYamlTest, LoadScenarioFileRejectsImplausibleQuantities) {
  const TempDir dir;
  const auto error_of = [&](const std::string& yaml) {
    const auto file = dir.Write("s.yaml", yaml);
    const std::string message = ErrorOf([&] { LoadScenarioFile(file); });
    EXPECT_THAT(message, HasSubstr(file.string() + ": ")) << yaml;
    return message;
  };
  EXPECT_THAT(error_of("world:\n  hall: {min_x_m: 0, min_y_m: 0, max_x_m: 1e308, max_y_m: 50}\n"),
              HasSubstr("world.hall: must be at most 100000 m in magnitude"));
  EXPECT_THAT(error_of("world:\n  hall: {min_x_m: 0, min_y_m: 0, max_x_m: 5000, max_y_m: 50}\n"),
              HasSubstr("world.hall: must be in [10, 1000] m (max_x_m - min_x_m)"));
  EXPECT_THAT(error_of("world:\n  corridor_length_m: 1e6\n"),
              HasSubstr("world.corridor_length_m: must be in (0, 1000] m"));
  EXPECT_THAT(error_of("world:\n  tag_size_m: 6\n"),
              HasSubstr("world.tag_size_m: must be in (0, 5] m"));
  EXPECT_THAT(error_of("world:\n  tag_regions: [{min_x_m: -1e9, min_y_m: 0, max_x_m: 1, "
                       "max_y_m: 1}]\n"),
              HasSubstr("world.tag_regions[0]: must be at most 100000 m in magnitude"));
  EXPECT_THAT(error_of("world:\n  rows:\n    - origin_m: [1e300, 0]\n"),
              HasSubstr("world.rows[0].origin_m: must be at most 100000 m in magnitude"));
  EXPECT_THAT(error_of("world:\n  rows:\n    - direction_deg: 720\n"),
              HasSubstr("world.rows[0].direction_deg: must be at most 360 deg in magnitude"));
  EXPECT_THAT(error_of("route:\n  loop_m: [[0, 0], [1e6, 0]]\n"),
              HasSubstr("route.loop_m[1]: must be at most 100000 m in magnitude"));
  EXPECT_THAT(error_of("route:\n  max_accel_mps2: 50\n"),
              HasSubstr("route.max_accel_mps2: must be in (0, 10] m/s^2"));
  EXPECT_THAT(error_of("vehicle:\n  length_m: 30\n"),
              HasSubstr("vehicle: length_m must be in (0, 20]"));
  EXPECT_THAT(error_of("vehicle:\n  max_road_wheel_rate_radps: 1e9\n"),
              HasSubstr("vehicle: max_road_wheel_rate_radps must be in (0, 10]"));
  EXPECT_THAT(error_of("sensors:\n  odometry:\n    wheel_speed_sigma_mps: 100\n"),
              HasSubstr("sensors.odometry.wheel_speed_sigma_mps: must be in [0, 60] m/s"));
  EXPECT_THAT(error_of("sensors:\n  odometry:\n    heading_sigma_rad: 7\n"),
              HasSubstr("sensors.odometry.heading_sigma_rad: must be in [0, 3.14159] rad"));
  EXPECT_THAT(error_of("sensors:\n  slots:\n    view_length_m: 80\n"),
              HasSubstr("sensors.slots.view_length_m: must be in [2, 50] m"));
  EXPECT_THAT(error_of("sensors:\n  slots:\n    corner_sigma_m: 9.95\n"),
              HasSubstr("sensors.slots.corner_sigma_m: grows beyond 10 m across the view"));
  EXPECT_THAT(error_of("sensors:\n  tags:\n    camera_x_m: 25\n"),
              HasSubstr("sensors.tags.camera_x_m: must be at most 20 m in magnitude"));
  EXPECT_THAT(error_of("sensors:\n  tags:\n    max_range_m: 99\n"),
              HasSubstr("sensors.tags.max_range_m: reaches beyond 100 m from the vehicle"));
  EXPECT_THAT(error_of("sensors:\n  tags:\n    yaw_sigma_per_m: 1\n"),
              HasSubstr("sensors.tags.yaw_sigma_rad: grows beyond 3.14159 rad at max_range_m"));
  EXPECT_THAT(error_of("sensors:\n  tags:\n    bearing_sigma_rad: 1\n"),
              HasSubstr("sensors.tags.bearing_sigma_rad: gives more than 10 m across the line "
                        "of sight at max_range_m"));
}

TEST(ScenarioYamlTest, LoadScenarioFileOfAMissingFileNamesIt) {
  const TempDir dir;
  EXPECT_THAT(ErrorOf([&] { LoadScenarioFile(dir / "absent.yaml"); }), HasSubstr("absent.yaml"));
}

}  // namespace
}  // namespace parkslam::io
