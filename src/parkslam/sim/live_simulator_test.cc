#include "parkslam/sim/live_simulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <variant>

#include "parkslam/common/angles.h"

namespace parkslam::sim {
namespace {

// The entrance of the corridor, heading east into the hall.
const SE2 kStart(-37.0, 9.1, 0.0);

const Simulation& BatchSimulation() {
  static const Simulation sim = Simulate(DefaultScenario(), 1);
  return sim;
}

// Steps `steps` times with fixed commands, appending the events.
void Drive(LiveSimulator& sim, int steps, double speed_mps, double angle_rad,
           std::vector<SensorEvent>* events) {
  for (int i = 0; i < steps; ++i) sim.Step(speed_mps, angle_rad, events);
}

template <typename T>
std::vector<T> EventsOf(const std::vector<SensorEvent>& events) {
  std::vector<T> out;
  for (const SensorEvent& e : events) {
    if (const T* x = std::get_if<T>(&e)) out.push_back(*x);
  }
  return out;
}

// Every number an event carries, for exact comparisons.
std::vector<double> Flatten(const SensorEvent& event) {
  std::vector<double> v{static_cast<double>(event.index()), static_cast<double>(EventTime(event))};
  if (const auto* w = std::get_if<WheelSpeed>(&event)) v.push_back(w->speed_mps);
  if (const auto* s = std::get_if<SteeringAngle>(&event)) v.push_back(s->steering_wheel_rad);
  if (const auto* m = std::get_if<ImuSample>(&event)) {
    v.insert(v.end(), {m->yaw_rate_radps, m->heading_rad.value_or(-100.0)});
  }
  if (const auto* f = std::get_if<SlotObservationFrame>(&event)) {
    for (const SlotObservation& o : f->slots) {
      for (const Eigen::Vector2d& c : o.corners_vehicle) v.insert(v.end(), {c.x(), c.y()});
      v.push_back(o.id.confidence());
    }
  }
  if (const auto* f = std::get_if<TagObservationFrame>(&event)) {
    for (const TagObservation& o : f->tags) {
      v.insert(v.end(),
               {static_cast<double>(o.tag_id), o.range_m, o.bearing_rad, o.yaw_vehicle_rad});
    }
  }
  return v;
}

std::vector<SensorEvent> WeavingDrive(std::uint64_t seed) {
  LiveSimulator sim(DefaultScenario(), seed, kStart);
  std::vector<SensorEvent> events;
  for (int i = 0; i < 3000; ++i) sim.Step(2.0, 0.2 * std::sin(0.01 * i), &events);
  return events;
}

TEST(LiveSimulatorTest, SameSeedSameEvents) {
  const std::vector<SensorEvent> a = WeavingDrive(5), b = WeavingDrive(5);
  ASSERT_EQ(a.size(), b.size());
  int tags_seen = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(Flatten(a[i]), Flatten(b[i])) << i;
    if (const auto* f = std::get_if<TagObservationFrame>(&a[i]))
      tags_seen += static_cast<int>(f->tags.size());
  }
  EXPECT_GT(tags_seen, 100);  // the comparison covered tag observations
}

TEST(LiveSimulatorTest, OtherSeedOtherNoise) {
  const std::vector<SensorEvent> a = WeavingDrive(5), b = WeavingDrive(6);
  ASSERT_EQ(a.size(), b.size());              // the same schedule...
  EXPECT_NE(Flatten(a[10]), Flatten(b[10]));  // ...with other noise
}

TEST(LiveSimulatorTest, WorldIsTheBatchSimulatorsLotWhateverTheSeed) {
  const World& lot = BatchSimulation().world;  // drive seed 1
  const LiveSimulator sim(DefaultScenario(), 9, kStart);
  ASSERT_EQ(sim.world().slots.size(), lot.slots.size());
  for (size_t i = 0; i < lot.slots.size(); ++i) {
    EXPECT_EQ(sim.world().slots[i].painted_id, lot.slots[i].painted_id) << i;
    EXPECT_EQ(sim.world().slots[i].id_legible, lot.slots[i].id_legible) << i;
  }
  ASSERT_EQ(sim.world().tags.size(), lot.tags.size());
  for (size_t i = 0; i < lot.tags.size(); ++i) {
    EXPECT_EQ(sim.world().tags[i].p_map, lot.tags[i].p_map) << i;
  }
}

TEST(LiveSimulatorTest, SensorsRunAtTheirRatesInTimeOrder) {
  LiveSimulator sim(DefaultScenario(), 1, kStart);
  std::vector<SensorEvent> events;
  TimeNs previous_step_ns = 0;
  for (int i = 0; i < 2000; ++i) {  // 20 s
    const size_t first_new = events.size();
    sim.Step(2.0, 0.0, &events);
    for (size_t k = first_new; k < events.size(); ++k) {
      // Due in (t, t + dt], the first step also at t = 0; in time order.
      if (i > 0) {
        EXPECT_GT(EventTime(events[k]), previous_step_ns);
      }
      EXPECT_LE(EventTime(events[k]), sim.time_ns());
      if (k > 0) {
        EXPECT_GE(EventTime(events[k]), EventTime(events[k - 1]));
      }
    }
    previous_step_ns = sim.time_ns();
  }
  EXPECT_EQ(sim.time_ns(), 20 * kNanosecondsPerSecond);
  // Samples at t = 0, 1/rate, ... 20 s inclusive; tags at 0.05, 0.15, ... 19.95 s.
  EXPECT_EQ(EventsOf<WheelSpeed>(events).size(), 1001u);
  EXPECT_EQ(EventsOf<SteeringAngle>(events).size(), 1001u);
  EXPECT_EQ(EventsOf<ImuSample>(events).size(), 2001u);
  const auto slots = EventsOf<SlotObservationFrame>(events);
  const auto tags = EventsOf<TagObservationFrame>(events);
  ASSERT_EQ(slots.size(), 201u);
  ASSERT_EQ(tags.size(), 200u);
  for (size_t k = 0; k < tags.size(); ++k) {
    EXPECT_EQ(slots[k].t_ns, FromSeconds(0.1 * k));
    EXPECT_EQ(tags[k].t_ns - slots[k].t_ns, 50'000'000);
  }
}

TEST(LiveSimulatorTest, StraightDriveReachesExpectedDistance) {
  LiveSimulator sim(DefaultScenario(), 1, kStart);
  std::vector<SensorEvent> events;
  Drive(sim, 3000, 2.0, 0.0, &events);  // 30 s
  // From rest at 0.5 m/s^2 to 2 m/s (4 s, 4 m), then 26 s at 2 m/s.
  const double expected_m = 2.0 * 2.0 / (2 * 0.5) + 2.0 * 26.0;
  const Eigen::Vector2d moved = sim.state().T_map_vehicle.translation() - kStart.translation();
  EXPECT_NEAR(moved.x(), expected_m, 0.01 * expected_m);
  EXPECT_NEAR(moved.y(), 0.0, 1e-9);
  EXPECT_NEAR(sim.state().speed_mps, 2.0, 1e-12);
}

TEST(LiveSimulatorTest, ConstantSteeringDrivesBicycleCircle) {
  const VehicleParameters vehicle = DefaultScenario().vehicle;
  const double angle_rad = 0.3, radius_m = vehicle.wheelbase_m / std::tan(angle_rad);
  LiveSimulator sim(DefaultScenario(), 1, kStart);
  std::vector<SensorEvent> events;
  Drive(sim, 100, 2.0, angle_rad, &events);  // the wheel reaches 0.3 rad in 0.6 s
  ASSERT_NEAR(sim.state().road_wheel_angle_rad, angle_rad, 1e-15);
  auto centre = [&] {
    const SE2& T = sim.state().T_map_vehicle;
    return T * Eigen::Vector2d(0.0, radius_m);  // radius_m to the left
  };
  const Eigen::Vector2d centre_map = centre();
  for (int i = 0; i < 30; ++i) {  // 30 s, more than one turn
    Drive(sim, 100, 2.0, angle_rad, &events);
    EXPECT_NEAR((sim.state().T_map_vehicle.translation() - centre_map).norm(), radius_m, 1e-6);
    EXPECT_NEAR((centre() - centre_map).norm(), 0.0, 1e-6);
  }
  EXPECT_NEAR(sim.state().yaw_rate_radps, 2.0 / radius_m, 1e-12);
}

TEST(LiveSimulatorTest, SteeringRateAndAngleLimited) {
  const VehicleParameters vehicle = DefaultScenario().vehicle;  // 0.61 rad, 0.5 rad/s
  LiveSimulator sim(DefaultScenario(), 1, kStart);
  std::vector<SensorEvent> events;
  double previous = 0.0;
  for (int i = 0; i < 200; ++i) {
    const double angle = sim.Step(1.0, 1.0, &events).road_wheel_angle_rad;
    EXPECT_LE(angle - previous, vehicle.max_road_wheel_rate_radps * 0.01 + 1e-12);
    EXPECT_LE(angle, vehicle.max_road_wheel_angle_rad);
    if (i == 99) {
      EXPECT_NEAR(angle, 0.5, 1e-9);  // 1 s at the rate limit
    }
    previous = angle;
  }
  EXPECT_EQ(previous, vehicle.max_road_wheel_angle_rad);  // held at the limit
  // A command just inside the limit is reached and held.
  Drive(sim, 300, 1.0, -0.6, &events);  // 1.21 rad at 0.5 rad/s: 2.42 s
  EXPECT_NEAR(sim.state().road_wheel_angle_rad, -0.6, 1e-12);
}

TEST(LiveSimulatorTest, SpeedChangeLimitedByAccelerationAndDeceleration) {
  const RouteConfig limits = DefaultScenario().route;  // 0.5 and 0.7 m/s^2
  LiveSimulator sim(DefaultScenario(), 1, kStart);
  std::vector<SensorEvent> events;
  double previous = 0.0;
  for (int i = 0; i < 100; ++i) {
    const double speed = sim.Step(5.0, 0.0, &events).speed_mps;
    EXPECT_LE(speed - previous, limits.max_accel_mps2 * 0.01 + 1e-12);
    previous = speed;
  }
  EXPECT_NEAR(previous, 0.5, 1e-9);
  // Reversing: brake at 0.7 m/s^2 down to rest, then speed up backwards.
  for (int i = 0; i < 150; ++i) {
    const double speed = sim.Step(-1.0, 0.0, &events).speed_mps;
    const double limit = (previous > 0.0 ? limits.max_decel_mps2 : limits.max_accel_mps2) * 0.01;
    EXPECT_LE(std::abs(speed - previous), limit + 1e-12) << i;
    if (i == 50) {
      EXPECT_NEAR(speed, 0.5 - 0.7 * 0.51, 1e-9);
    }
    previous = speed;
  }
  // 0.5 m/s braked away in 72 steps; then 78 steps at 0.005 m/s each.
  EXPECT_NEAR(previous, -0.39, 1e-9);
}

TEST(LiveSimulatorTest, ReplayingBatchCommandsReproducesBatchTrajectory) {
  const Simulation& batch = BatchSimulation();
  LiveSimulator sim(DefaultScenario(), 1, batch.states.front().T_map_vehicle);
  std::vector<SensorEvent> events;
  const size_t steps = 6000;  // 60 s at 100 Hz
  ASSERT_GT(batch.states.size(), steps);
  for (size_t i = 1; i <= steps; ++i) {
    sim.Step(batch.states[i].speed_mps, batch.states[i].road_wheel_angle_rad, &events);
  }
  const VehicleState& truth = batch.states[steps];
  EXPECT_EQ(sim.time_ns(), truth.t_ns);
  EXPECT_LT((sim.state().T_map_vehicle.translation() - truth.T_map_vehicle.translation()).norm(),
            0.05);
  EXPECT_GT((truth.T_map_vehicle.translation() - kStart.translation()).norm(), 100.0);
}

TEST(LiveSimulatorTest, ReplayedDriveHasTheBatchOdometryNoise) {
  // The same seed draws the same per-sensor streams as the batch simulator.
  const Simulation& batch = BatchSimulation();
  LiveSimulator sim(DefaultScenario(), 1, batch.states.front().T_map_vehicle);
  std::vector<SensorEvent> events;
  for (size_t i = 1; i <= 1000; ++i) {
    sim.Step(batch.states[i].speed_mps, batch.states[i].road_wheel_angle_rad, &events);
  }
  const auto wheel = EventsOf<WheelSpeed>(events);
  const auto imu = EventsOf<ImuSample>(events);
  ASSERT_EQ(wheel.size(), 501u);
  ASSERT_EQ(imu.size(), 1001u);
  for (size_t k = 0; k < wheel.size(); ++k) {
    EXPECT_EQ(wheel[k].t_ns, batch.log.wheel_speeds[k].t_ns);
    EXPECT_NEAR(wheel[k].speed_mps, batch.log.wheel_speeds[k].speed_mps, 1e-9);
  }
  for (size_t k = 0; k < imu.size(); ++k) {
    EXPECT_NEAR(imu[k].yaw_rate_radps, batch.log.imu_samples[k].yaw_rate_radps, 1e-9);
    ASSERT_TRUE(imu[k].heading_rad && batch.log.imu_samples[k].heading_rad);
    EXPECT_NEAR(AngleDiff(*imu[k].heading_rad, *batch.log.imu_samples[k].heading_rad), 0.0, 1e-9);
  }
}

TEST(LiveSimulatorTest, TeleportedCarSeesSlotsAroundItsNewPose) {
  LiveSimulator sim(DefaultScenario(), 1, kStart);
  std::vector<SensorEvent> events;
  Drive(sim, 200, 1.0, 0.0, &events);  // in the corridor: no slots there
  EXPECT_TRUE(sim.last_slot_labels().empty());
  const double speed_mps = sim.state().speed_mps;

  // In the aisle 3 m in front of slot 100 (ID 108, in the north of the
  // hall), facing along its entrance, so the slot lies to the left.
  const WorldSlot& slot = sim.world().slots.at(100);
  const Eigen::Vector2d along = (slot.corners_map[1] - slot.corners_map[0]).normalized();
  const Eigen::Vector2d inward = (slot.corners_map[3] - slot.corners_map[0]).normalized();
  const Eigen::Vector2d entrance_mid = (slot.corners_map[0] + slot.corners_map[1]) / 2;
  const SE2 target(entrance_mid - 3.0 * inward, std::atan2(along.y(), along.x()));
  ASSERT_GT((target.translation() - sim.state().T_map_vehicle.translation()).norm(), 30.0);
  sim.Teleport(target);
  EXPECT_EQ(sim.state().T_map_vehicle.translation(), target.translation());
  EXPECT_EQ(sim.state().speed_mps, speed_mps);

  events.clear();
  while (EventsOf<SlotObservationFrame>(events).empty()) sim.Step(0.0, 0.0, &events);
  const std::vector<int>& labels = sim.last_slot_labels();
  int true_slots = 0;
  for (int label : labels) {
    if (label < 0) continue;
    ++true_slots;
    const WorldSlot& seen = sim.world().slots.at(label);
    // Entrance corners inside the 10 m x 10 m top view around the car.
    EXPECT_LT((seen.corners_map[0] - target.translation()).norm(), 8.2) << label;
  }
  EXPECT_GE(true_slots, 2);
}

TEST(LiveSimulatorTest, StreamedOdometryNoiseMatchesConfiguration) {
  ScenarioConfig scenario = DefaultScenario();
  scenario.sensors.odometry.gyro_bias_walk_radps_per_sqrt_s = 0.0;
  const OdometrySensorConfig& config = scenario.sensors.odometry;
  LiveSimulator sim(scenario, 3, kStart);
  std::vector<SensorEvent> events;
  Drive(sim, 500, 2.0, 0.0, &events);  // up to speed
  events.clear();
  Drive(sim, 12000, 2.0, 0.0, &events);  // 2 min straight: yaw rate 0
  auto sigma = [](const std::vector<double>& x) {
    double mean = 0, sum2 = 0;
    for (double v : x) mean += v / x.size();
    for (double v : x) sum2 += (v - mean) * (v - mean);
    return std::sqrt(sum2 / x.size());
  };
  std::vector<double> wheel, gyro;
  for (const WheelSpeed& w : EventsOf<WheelSpeed>(events)) wheel.push_back(w.speed_mps);
  for (const ImuSample& m : EventsOf<ImuSample>(events)) gyro.push_back(m.yaw_rate_radps);
  ASSERT_EQ(wheel.size(), 6000u);
  ASSERT_EQ(gyro.size(), 12000u);
  // Standard errors of the estimated sigmas: 1.8e-4 and 3.2e-5.
  EXPECT_NEAR(sigma(wheel), config.wheel_speed_sigma_mps, 0.001);
  EXPECT_NEAR(sigma(gyro), config.gyro_sigma_radps, 0.00015);
}

TEST(LiveSimulatorTest, InvalidStepRateThrows) {
  LiveSimulatorOptions options;
  options.step_hz = 0.0;
  EXPECT_THROW(LiveSimulator(DefaultScenario(), 1, kStart, options), std::invalid_argument);
  options.step_hz = 1.0;
  EXPECT_NO_THROW(LiveSimulator(DefaultScenario(), 1, kStart, options));
}

// A realistic vehicle (VehicleDynamics): commands act late, the speed lags,
// the tyres slip in turns.
TEST(LiveSimulatorTest, RealisticDynamicsDelayLagAndSlip) {
  LiveSimulatorOptions realistic;
  realistic.dynamics = RealisticDynamics();
  std::vector<SensorEvent> events;
  // Delay: a speed command given at t = 0 moves the car only after 0.15 s.
  LiveSimulator delayed(DefaultScenario(), 1, kStart, realistic);
  Drive(delayed, 15, 0.2, 0.0, &events);
  EXPECT_EQ(delayed.state().speed_mps, 0.0);
  Drive(delayed, 1, 0.2, 0.0, &events);
  EXPECT_GT(delayed.state().speed_mps, 0.0);
  // Lag: 0.5 s after the command acts the speed is 1 - 1/e of the way (the
  // route's acceleration limit would allow 0.25 m/s).
  Drive(delayed, 49, 0.2, 0.0, &events);
  EXPECT_NEAR(delayed.state().speed_mps, 0.2 * (1.0 - std::exp(-1.0)), 0.003);

  // Slip: at 3 m/s on a steady turn the yaw rate is below the kinematic
  // bicycle's, and the car's track is wider than the ideal car's.
  LiveSimulator ideal(DefaultScenario(), 1, kStart);
  LiveSimulator slipping(DefaultScenario(), 1, kStart, realistic);
  const double angle = 0.2;
  Drive(ideal, 800, 3.0, angle, &events);
  Drive(slipping, 800, 3.0, angle, &events);
  const double kinematic = 3.0 * std::tan(angle) / DefaultScenario().vehicle.wheelbase_m;
  EXPECT_NEAR(ideal.state().yaw_rate_radps, kinematic, 1e-9);
  EXPECT_LT(slipping.state().yaw_rate_radps, 0.99 * kinematic);
  EXPECT_GT(slipping.state().yaw_rate_radps, 0.9 * kinematic);
  EXPECT_DOUBLE_EQ(slipping.state().road_wheel_angle_rad, angle);  // what the sensor reads
  // The gyro measures the yaw rate the car really turns at.
  const std::vector<ImuSample> imu = EventsOf<ImuSample>(events);
  EXPECT_NEAR(imu.back().yaw_rate_radps, slipping.state().yaw_rate_radps, 0.03);

  LiveSimulatorOptions bad;
  bad.dynamics.actuator_delay_s = -0.1;
  EXPECT_THROW(LiveSimulator(DefaultScenario(), 1, kStart, bad), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::sim
