#include "parkslam/odometry/odometry_ekf.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <optional>

#include "parkslam/common/angles.h"

namespace parkslam::odometry {
namespace {

constexpr TimeNs kMs = 1'000'000;

// Feeds perfect measurements of a vehicle moving at speed v on a circle of
// road-wheel angle delta (straight for delta = 0) for `seconds`.
void Drive(OdometryEkf& ekf, const OdometryEkfOptions& o, double v, double delta, double gyro_bias,
           double seconds) {
  const double omega = v * std::tan(delta) / o.vehicle.wheelbase_m;
  const TimeNs start = ekf.time_ns();
  double yaw = ekf.pose().yaw();
  for (TimeNs t = start + 10 * kMs; t <= start + FromSeconds(seconds); t += 10 * kMs) {
    yaw += omega * 0.01;
    ekf.Process(WheelSpeed{t, v});
    ekf.Process(SteeringAngle{t, delta * o.vehicle.steering_ratio});
    ekf.Process(ImuSample{t, omega + gyro_bias, NormalizeAngle(yaw)});
  }
}

// A car speeding up at 0.5 m/s^2 on a circle: the filter learns the
// acceleration, and its distance keeps up with the truth; with the
// acceleration states switched off (no jerk, no prior) they stay at zero
// and the speed, a random walk, lags behind.
TEST(OdometryEkfTest, TheAccelerationIsLearntAndCanBeSwitchedOff) {
  for (const bool with_acceleration : {true, false}) {
    OdometryEkfOptions o;
    if (!with_acceleration) {
      o.jerk_sigma_mps3_per_sqrt_hz = o.yaw_jerk_sigma_radps3_per_sqrt_hz = 0.0;
      o.initial_accel_sigma_mps2 = o.initial_yaw_accel_sigma_radps2 = 0.0;
    }
    OdometryEkf ekf(o);
    ekf.Initialize(0, SE2(0, 0, 0), 0.001);
    const double a = 0.5, delta = 0.1;
    double v = 0.5, distance = 0.0;
    for (TimeNs t = 10 * kMs; t <= FromSeconds(6.0); t += 10 * kMs) {
      distance += (v + 0.5 * a * 0.01) * 0.01;
      v += a * 0.01;
      const double omega = v * std::tan(delta) / o.vehicle.wheelbase_m;
      ekf.Process(WheelSpeed{t, v});
      ekf.Process(SteeringAngle{t, delta * o.vehicle.steering_ratio});
      ekf.Process(ImuSample{t, omega, std::nullopt});
    }
    const double speed_lag = v - ekf.state()[OdometryEkf::kSpeed];
    if (with_acceleration) {
      EXPECT_NEAR(ekf.state()[OdometryEkf::kAccel], a, 0.05);
      EXPECT_LT(std::abs(speed_lag), 0.002);
    } else {
      EXPECT_EQ(ekf.state()[OdometryEkf::kAccel], 0.0);
      EXPECT_EQ(ekf.state()[OdometryEkf::kYawAccel], 0.0);
      EXPECT_GT(speed_lag, 0.002);
    }
    EXPECT_GT(distance, 10.0);
  }
}

TEST(OdometryEkfTest, WithoutACompassTheYawFollowsTheGyroFromZero) {
  OdometryEkfOptions o;
  OdometryEkf ekf(o);
  ekf.InitializeFromHeading(0, {1.0, 2.0}, std::nullopt);
  EXPECT_EQ(ekf.pose().yaw(), 0.0);
  EXPECT_EQ(ekf.covariance()(OdometryEkf::kYaw, OdometryEkf::kYaw), 0.0);
  // Half a circle on gyro, wheel speed and steering alone.
  const double v = 2.0, delta = 0.2;
  const double omega = v * std::tan(delta) / o.vehicle.wheelbase_m;
  for (TimeNs t = 10 * kMs; t <= FromSeconds(kPi / omega); t += 10 * kMs) {
    ekf.Process(WheelSpeed{t, v});
    ekf.Process(SteeringAngle{t, delta * o.vehicle.steering_ratio});
    ekf.Process(ImuSample{t, omega, std::nullopt});
  }
  EXPECT_NEAR(std::abs(ekf.pose().yaw()), kPi, 0.02);
  EXPECT_EQ(ekf.stats().rejected[OdometryEkfStats::kHeading], 0);
}

// A compass bent by 0.1 rad for 2 m of driving (a pillar beside the lane)
// moves the yaw by little: over metres the gyro carries the yaw, and the
// disturbance state, a Gauss-Markov process in distance, takes the bend.
TEST(OdometryEkfTest, ACompassBentForAFewMetresBarelyMovesTheYaw) {
  OdometryEkfOptions o;
  OdometryEkf ekf(o);
  ekf.Initialize(0, SE2(0, 0, 0), 0.001);
  const double v = 2.0;
  for (TimeNs t = 10 * kMs; t <= FromSeconds(20.0); t += 10 * kMs) {
    const double bend_rad = (t > FromSeconds(10.0) && t <= FromSeconds(11.0)) ? 0.1 : 0.0;
    ekf.Process(WheelSpeed{t, v});
    ekf.Process(SteeringAngle{t, 0.0});
    ekf.Process(ImuSample{t, 0.0, bend_rad});
    if (t == FromSeconds(11.0)) {
      EXPECT_LT(std::abs(ekf.pose().yaw()), 0.02);
      EXPECT_GT(ekf.state()[OdometryEkf::kHeadingDisturbance], 0.05);
    }
  }
  EXPECT_LT(std::abs(ekf.pose().yaw()), 0.01);
  EXPECT_LT(std::abs(ekf.pose().y()), 0.3);
}

TEST(OdometryEkfTest, StraightDriveIntegratesDistance) {
  OdometryEkfOptions o;
  OdometryEkf ekf(o);
  ekf.Initialize(0, SE2(0, 0, 0), 0.01);
  Drive(ekf, o, 2.0, 0.0, 0.0, 10.0);
  // The speed state starts at 0 and converges within a few samples.
  EXPECT_NEAR(ekf.pose().x(), 20.0, 0.1);
  EXPECT_NEAR(ekf.pose().y(), 0.0, 1e-3);
  EXPECT_NEAR(ekf.state()[OdometryEkf::kSpeed], 2.0, 1e-3);
}

TEST(OdometryEkfTest, CircleReturnsToStart) {
  OdometryEkfOptions o;
  OdometryEkf ekf(o);
  ekf.Initialize(0, SE2(0, 0, 0), 0.01);
  const double v = 2.0, delta = 0.2;
  const double omega = v * std::tan(delta) / o.vehicle.wheelbase_m;
  Drive(ekf, o, v, delta, 0.0, 2 * kPi / omega + 0.05);
  EXPECT_LT(ekf.pose().translation().norm(), 0.3);
  EXPECT_NEAR(ekf.state()[OdometryEkf::kYawRate], omega, 1e-3);
}

TEST(OdometryEkfTest, GyroBiasIsEstimatedFromSteering) {
  OdometryEkfOptions o;
  OdometryEkf ekf(o);
  ekf.Initialize(0, SE2(0, 0, 0), 0.01);
  Drive(ekf, o, 2.0, 0.1, 0.004, 60.0);
  EXPECT_NEAR(ekf.state()[OdometryEkf::kGyroBias], 0.004, 3e-4);
}

TEST(OdometryEkfTest, HeadingInitialisationCorrelatesYawAndBias) {
  OdometryEkfOptions o;
  OdometryEkf ekf(o);
  ekf.InitializeFromHeading(0, {1.0, 2.0}, 0.5);
  const auto& P = ekf.covariance();
  EXPECT_NEAR(P(OdometryEkf::kYaw, OdometryEkf::kHeadingBias),
              -o.heading_bias_sigma_rad * o.heading_bias_sigma_rad, 1e-15);
  EXPECT_NEAR(P(OdometryEkf::kYaw, OdometryEkf::kHeadingDisturbance),
              -o.heading_disturbance_sigma_rad * o.heading_disturbance_sigma_rad, 1e-15);
  EXPECT_NEAR(std::sqrt(P(OdometryEkf::kYaw, OdometryEkf::kYaw)),
              std::sqrt(o.heading_bias_sigma_rad * o.heading_bias_sigma_rad +
                        o.heading_disturbance_sigma_rad * o.heading_disturbance_sigma_rad +
                        o.heading_sigma_rad * o.heading_sigma_rad),
              1e-12);
  EXPECT_EQ(ekf.pose().x(), 1.0);
}

TEST(OdometryEkfTest, CovarianceGrowsWhileDriving) {
  OdometryEkfOptions o;
  OdometryEkf ekf(o);
  ekf.Initialize(0, SE2(0, 0, 0), 0.01);
  Drive(ekf, o, 2.0, 0.0, 0.0, 5.0);
  const double early = ekf.pose_covariance().trace();
  Drive(ekf, o, 2.0, 0.0, 0.0, 50.0);
  EXPECT_GT(ekf.pose_covariance().trace(), 2.0 * early);
  // Symmetric and positive definite throughout.
  const auto& P = ekf.covariance();
  EXPECT_LT((P - P.transpose()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT(P.ldlt().vectorD().minCoeff(), 0.0);
}

TEST(OdometryEkfTest, RelativeMotionSinceCloneHasItsOwnCovariance) {
  OdometryEkfOptions o;
  OdometryEkf ekf(o);
  ekf.Initialize(0, SE2(5, 5, 1.0), 0.05);
  Drive(ekf, o, 2.0, 0.0, 0.0, 30.0);  // the absolute covariance has grown
  ekf.ClonePose();
  const double absolute_before = ekf.pose_covariance().trace();
  Drive(ekf, o, 2.0, 0.1, 0.0, 1.0);
  const auto motion = ekf.MotionSinceClone();
  // About 2 m of motion, expressed in the clone's frame.
  EXPECT_NEAR(motion.T_clone_now.translation().norm(), 2.0, 0.05);
  EXPECT_GT(motion.T_clone_now.yaw(), 0.0);
  // The increment is far more certain than the absolute pose.
  EXPECT_LT(motion.covariance.trace(), 0.1 * absolute_before);
  EXPECT_GT(motion.covariance(0, 0), 0.0);
  EXPECT_GT(motion.covariance(2, 2), 0.0);
  EXPECT_LT((motion.covariance - motion.covariance.transpose()).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(OdometryEkfTest, CloneDoesNotChangeTheEstimate) {
  OdometryEkfOptions o;
  OdometryEkf a(o), b(o);
  a.Initialize(0, SE2(0, 0, 0), 0.01);
  b.Initialize(0, SE2(0, 0, 0), 0.01);
  Drive(a, o, 2.0, 0.1, 0.002, 5.0);
  Drive(b, o, 2.0, 0.1, 0.002, 5.0);
  b.ClonePose();
  Drive(a, o, 2.0, 0.1, 0.002, 5.0);
  Drive(b, o, 2.0, 0.1, 0.002, 5.0);
  EXPECT_NEAR(a.pose().x(), b.pose().x(), 1e-9);
  EXPECT_NEAR(a.pose_covariance()(0, 0), b.pose_covariance()(0, 0), 1e-12);
}

TEST(OdometryEkfTest, RejectsEventsBeforeFilterTimeOrBeforeInit) {
  OdometryEkfOptions o;
  OdometryEkf ekf(o);
  EXPECT_FALSE(ekf.Process(WheelSpeed{0, 1.0}));
  ekf.Initialize(100 * kMs, SE2(), 0.01);
  EXPECT_FALSE(ekf.Process(WheelSpeed{50 * kMs, 1.0}));
  EXPECT_TRUE(ekf.Process(WheelSpeed{100 * kMs, 1.0}));
}

TEST(OdometryEkfTest, InvalidOptionsAreRejected) {
  OdometryEkfOptions o;
  std::string error;
  EXPECT_TRUE(o.IsValid(&error));
  o.gyro_sigma_radps = -1.0;
  EXPECT_FALSE(o.IsValid(&error));
  o.gyro_sigma_radps = 0.0;
  EXPECT_FALSE(o.IsValid(&error));
}

// Faults (docs/robustness.md): a one-sample spike is gated out; a heading
// that jumps and stays is taken by the heading bias after the reset time,
// and yaw (from the gyroscope) does not follow it.
TEST(OdometryEkfTest, GatesImuSpikesAndTakesAHeadingJumpAsBias) {
  OdometryEkfOptions o;
  for (const bool gated : {true, false}) {
    if (!gated) o.innovation_gate_chi2 = 1e12;  // a gate nothing fails
    OdometryEkf ekf(o);
    ekf.Initialize(0, SE2(0, 0, 0), 0.01);
    Drive(ekf, o, 2.0, 0.0, 0.0, 5.0);
    // One gyro spike of 3 rad/s and one wheel-speed spike of 20 m/s.
    const TimeNs t = ekf.time_ns() + 10 * kMs;
    ekf.Process(WheelSpeed{t, 20.0});
    ekf.Process(ImuSample{t, 3.0, 0.0});
    Drive(ekf, o, 2.0, 0.0, 0.0, 5.0);
    if (gated) {
      EXPECT_EQ(ekf.stats().rejected[OdometryEkfStats::kGyro], 1);
      EXPECT_EQ(ekf.stats().rejected[OdometryEkfStats::kWheelSpeed], 1);
      EXPECT_NEAR(ekf.pose().yaw(), 0.0, 1e-3);
      EXPECT_NEAR(ekf.pose().x(), 20.0, 0.15);
    } else {
      // Without the gate the same spikes bend and stretch the track.
      EXPECT_EQ(ekf.stats().rejected[OdometryEkfStats::kGyro], 0);
      EXPECT_GT(std::abs(ekf.pose().y()) + std::abs(ekf.pose().x() - 20.0), 0.2);
    }
  }
}

TEST(OdometryEkfTest, HeadingJumpIsAbsorbedByTheHeadingBias) {
  OdometryEkfOptions o;
  OdometryEkf ekf(o);
  ekf.Initialize(0, SE2(0, 0, 0), 0.01);
  Drive(ekf, o, 2.0, 0.0, 0.0, 5.0);
  // From now on the AHRS reads 0.4 rad more than the true heading (0).
  const TimeNs start = ekf.time_ns();
  for (TimeNs t = start + 10 * kMs; t <= start + FromSeconds(10.0); t += 10 * kMs) {
    ekf.Process(WheelSpeed{t, 2.0});
    ekf.Process(SteeringAngle{t, 0.0});
    ekf.Process(ImuSample{t, 0.0, 0.4});
  }
  const OdometryEkfStats& stats = ekf.stats();
  EXPECT_EQ(stats.resets[OdometryEkfStats::kHeading], 1);
  // Rejected for fault_reset_after_s at 100 Hz, then taken.
  EXPECT_NEAR(stats.rejected[OdometryEkfStats::kHeading], 100, 2);
  EXPECT_NEAR(ekf.state()[OdometryEkf::kHeadingBias], 0.4, 0.01);
  EXPECT_NEAR(ekf.pose().yaw(), 0.0, 0.01);
  EXPECT_NEAR(ekf.pose().y(), 0.0, 0.1);
}

TEST(OdometryEkfTest, CountsLateEventsAndSensorGaps) {
  OdometryEkfOptions o;
  OdometryEkf ekf(o);
  ekf.Initialize(0, SE2(0, 0, 0), 0.01);
  Drive(ekf, o, 2.0, 0.0, 0.0, 2.0);
  EXPECT_FALSE(ekf.Process(WheelSpeed{ekf.time_ns() - 5 * kMs, 2.0}));
  EXPECT_EQ(ekf.stats().late_events, 1);
  // Wheel speed silent for 3 s, the IMU not.
  const TimeNs start = ekf.time_ns();
  for (TimeNs t = start + 10 * kMs; t <= start + FromSeconds(3.0); t += 10 * kMs) {
    ekf.Process(ImuSample{t, 0.0, 0.0});
  }
  Drive(ekf, o, 2.0, 0.0, 0.0, 1.0);
  EXPECT_NEAR(ekf.stats().longest_gap_s[OdometryEkfStats::kWheelSpeed], 3.01, 1e-6);
  EXPECT_NEAR(ekf.stats().longest_gap_s[OdometryEkfStats::kGyro], 0.01, 1e-6);
  // Dead reckoning carried the car through the gap at its last speed.
  EXPECT_NEAR(ekf.pose().x(), 12.0, 0.1);
}

}  // namespace
}  // namespace parkslam::odometry
