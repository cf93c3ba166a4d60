#include "parkslam/sim/simulator.h"

#include <gtest/gtest.h>

#include <cmath>

#include "parkslam/common/angles.h"
#include "parkslam/sim/route.h"

namespace parkslam::sim {
namespace {

const Simulation& DefaultSimulation() {
  static const Simulation sim = Simulate(DefaultScenario(), 1);
  return sim;
}

TEST(RouteTest, BicycleStepFollowsCircle) {
  VehicleParameters vehicle;
  VehicleState s;
  const double delta = 0.3, v = 2.0;
  const double radius = vehicle.wheelbase_m / std::tan(delta);
  for (int i = 0; i < 1000; ++i) s = StepBicycle(s, v, delta, 0.01, vehicle);
  // Start at the origin heading +x: the circle's centre is (0, radius).
  EXPECT_NEAR((s.T_map_vehicle.translation() - Eigen::Vector2d(0, radius)).norm(), radius, 1e-9);
  EXPECT_NEAR(s.T_map_vehicle.yaw(), NormalizeAngle(v * 10.0 / radius), 1e-9);
}

TEST(RouteTest, WaypointsRepeatTheLoop) {
  RouteConfig route;
  route.approach_m = {{0, 0}};
  route.loop_m = {{1, 0}, {1, 1}};
  route.laps = 2;
  route.finish_m = {{5, 5}};
  const auto w = RouteWaypoints(route);
  ASSERT_EQ(w.size(), 7u);  // 0, (1,0) (1,1) x2, back to (1,0), (5,5)
  EXPECT_EQ(w[5], Eigen::Vector2d(1, 0));
}

TEST(DriveTest, DefaultDriveLooksHuman) {
  const Simulation& sim = DefaultSimulation();
  const VehicleParameters vehicle;
  double max_speed = 0, cruise_time = 0, total_time = 0;
  for (size_t i = 1; i < sim.states.size(); ++i) {
    const VehicleState& s = sim.states[i];
    max_speed = std::max(max_speed, s.speed_mps);
    EXPECT_LE(std::abs(s.road_wheel_angle_rad), vehicle.max_road_wheel_angle_rad + 1e-12);
    const double dt = ToSeconds(s.t_ns - sim.states[i - 1].t_ns);
    total_time += dt;
    if (s.speed_mps >= 3.0 / 3.6) cruise_time += dt;
    // Smooth speed: within the acceleration limits.
    EXPECT_LE(std::abs(s.speed_mps - sim.states[i - 1].speed_mps), 0.7 * dt + 1e-9);
  }
  EXPECT_LE(max_speed, 10.0 / 3.6);
  EXPECT_GE(max_speed, 8.0 / 3.6);
  EXPECT_GT(cruise_time / total_time, 0.9);
  EXPECT_NEAR(sim.states.front().speed_mps, 0.0, 1e-12);
  EXPECT_LT(sim.states.back().speed_mps, 0.1);
  const double length = PathLength(GroundTruthTrajectory(sim));
  EXPECT_GT(length, 450.0);
}

TEST(DriveTest, DriveStaysInsideTheLot) {
  const Simulation& sim = DefaultSimulation();
  const RegionConfig& hall = sim.world.hall;
  for (const VehicleState& s : sim.states) {
    const Eigen::Vector2d p = s.T_map_vehicle.translation();
    const bool in_hall = hall.Contains(p);
    const bool in_corridor = p.x() < hall.min_x_m && std::abs(p.y() - 9.1) < 1.5;
    ASSERT_TRUE(in_hall || in_corridor) << p.transpose();
  }
}

bool InsidePolygon(const std::array<Eigen::Vector2d, 4>& c, const Eigen::Vector2d& p) {
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d e = c[(i + 1) % 4] - c[i], d = p - c[i];
    if (e.x() * d.y() - e.y() * d.x() < 0.0) return false;  // right of a CCW edge
  }
  return true;
}

TEST(DriveTest, DriveNeverEntersASlotOrPillar) {
  const Simulation& sim = DefaultSimulation();
  for (const VehicleState& s : sim.states) {
    // The rear axle and the front of the car (3.7 m ahead).
    for (double ahead_m : {0.0, 3.7}) {
      const Eigen::Vector2d p = s.T_map_vehicle * Eigen::Vector2d(ahead_m, 0.0);
      for (const WorldSlot& slot : sim.world.slots) {
        ASSERT_FALSE(InsidePolygon(slot.corners_map, p)) << p.transpose();
      }
      for (const WorldPillar& pillar : sim.world.pillars) {
        ASSERT_GT((p - pillar.center_map).cwiseAbs().maxCoeff(), pillar.half_size_m);
      }
    }
  }
}

TEST(DriveTest, DrivePassesEarlierSlotsAgain) {
  const Simulation& sim = DefaultSimulation();
  std::vector<int> first_seen(sim.world.slots.size(), -1);
  int revisited = 0;
  for (size_t f = 0; f < sim.slot_labels.size(); ++f) {
    for (int label : sim.slot_labels[f]) {
      if (label < 0) continue;
      if (first_seen[label] < 0) {
        first_seen[label] = static_cast<int>(f);
      } else if (f - first_seen[label] > 600) {  // more than a minute later
        ++revisited;
        first_seen[label] = static_cast<int>(f);
      }
    }
  }
  EXPECT_GT(revisited, 30);
}

TEST(SimulatorTest, SameSeedSameData) {
  const Simulation a = Simulate(DefaultScenario(), 11);
  const Simulation b = Simulate(DefaultScenario(), 11);
  ASSERT_EQ(a.log.imu_samples.size(), b.log.imu_samples.size());
  for (size_t i = 0; i < a.log.imu_samples.size(); i += 97) {
    EXPECT_EQ(a.log.imu_samples[i].heading_rad, b.log.imu_samples[i].heading_rad);
  }
  ASSERT_EQ(a.log.slot_frames.size(), b.log.slot_frames.size());
  for (size_t i = 0; i < a.log.slot_frames.size(); ++i) {
    ASSERT_EQ(a.log.slot_frames[i].slots.size(), b.log.slot_frames[i].slots.size());
  }
  EXPECT_EQ(a.states.back().T_map_vehicle.x(), b.states.back().T_map_vehicle.x());
}

TEST(SimulatorTest, OtherSeedOtherNoise) {
  const Simulation a = Simulate(DefaultScenario(), 11);
  const Simulation b = Simulate(DefaultScenario(), 12);
  EXPECT_NE(a.log.imu_samples[100].yaw_rate_radps, b.log.imu_samples[100].yaw_rate_radps);
}

TEST(SimulatorTest, SensorRatesMatchConfig) {
  const Simulation& sim = DefaultSimulation();
  const double duration_s = ToSeconds(sim.states.back().t_ns - sim.states.front().t_ns);
  EXPECT_NEAR(sim.log.wheel_speeds.size() / duration_s, 50.0, 0.5);
  EXPECT_NEAR(sim.log.steering_angles.size() / duration_s, 50.0, 0.5);
  EXPECT_NEAR(sim.log.imu_samples.size() / duration_s, 100.0, 0.5);
  EXPECT_NEAR(sim.log.slot_frames.size() / duration_s, 10.0, 0.2);
  EXPECT_NEAR(sim.log.tag_frames.size() / duration_s, 10.0, 0.2);
}

TEST(SimulatorTest, InvalidScenarioThrows) {
  ScenarioConfig config = DefaultScenario();
  config.sensors.ids.confusion_rate = 0.7;
  config.sensors.ids.partial_rate = 0.5;
  EXPECT_THROW(Simulate(config, 1), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::sim
