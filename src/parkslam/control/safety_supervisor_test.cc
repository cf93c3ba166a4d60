#include "parkslam/control/safety_supervisor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace parkslam::control {
namespace {

const Eigen::Matrix2d kSmall = Eigen::Matrix2d::Identity() * 0.01;  // 0.1 m sigma

// Estimates of a localizer that tracks, or that is lost, with 0.1 m sigma.
void Tracking(SafetySupervisor* e, double t) { e->OnEstimate(FromSeconds(t), true, kSmall); }
void Lost(SafetySupervisor* e, double t) { e->OnEstimate(FromSeconds(t), false, kSmall); }

// Drives the supervisor at 100 Hz from t0 to t1 (s) with an estimate every
// 0.2 s as `estimate(t)` says; returns the last allowed speed. The car is
// measured at `measured` m/s (by default: as fast as it may).
template <typename Estimate>
double Drive(SafetySupervisor* supervisor, double t0, double t1, double cruise, Estimate estimate,
             double* stopped_at = nullptr, double measured = INFINITY) {
  double v = 0.0;
  for (int k = static_cast<int>(t0 * 100); k < static_cast<int>(t1 * 100); ++k) {
    const double t = k / 100.0;
    if (k % 20 == 0) estimate(supervisor, t);
    v = supervisor->AllowedSpeed(FromSeconds(t), 0.01, cruise, measured);
    if (stopped_at != nullptr && v == 0.0 && *stopped_at < 0) *stopped_at = t;
  }
  return v;
}

TEST(SafetySupervisorTest, CruisesWhileLocalizationIsHealthy) {
  SafetySupervisor s;
  const double v = Drive(&s, 0.0, 10.0, 2.78, Tracking);
  EXPECT_DOUBLE_EQ(v, 2.78);
  EXPECT_EQ(s.interventions(), 0);
}

TEST(SafetySupervisorTest, BrakesToAStopWhenLostAndGoesOnWhenBack) {
  SafetySupervisor s;
  Drive(&s, 0.0, 10.0, 2.78, Tracking);
  double stopped_at = -1.0;
  // Lost from t = 10 s: 2.78 m/s at 2.5 m/s^2 stops in 1.11 s.
  Drive(&s, 10.0, 20.0, 2.78, Lost, &stopped_at);
  EXPECT_NEAR(stopped_at, 10.0 + 2.78 / 2.5, 0.02);
  EXPECT_EQ(s.interventions(), 1);
  // Tracking again from t = 20 s: waits resume_after_s, then 1 m/s^2.
  const double v_soon = Drive(&s, 20.0, 20.9, 2.78, Tracking);
  EXPECT_DOUBLE_EQ(v_soon, 0.0);
  const double v_later = Drive(&s, 20.9, 22.5, 2.78, Tracking);
  EXPECT_NEAR(v_later, 1.5, 0.02);  // 1 m/s^2 from 21.0 s to 22.5 s
}

// Found in closed loop: lost in a turn at 7 km/h with a cap of 10 km/h,
// the car drove on for 0.3 s until the falling cap reached its speed.
TEST(SafetySupervisorTest, BrakesFromTheMeasuredSpeedNotFromTheCap) {
  SafetySupervisor s;
  Drive(&s, 0.0, 10.0, 2.78, Tracking);
  double stopped_at = -1.0;
  Drive(&s, 10.0, 14.0, 2.78, Lost, &stopped_at, 2.0);
  EXPECT_NEAR(stopped_at, 10.0 + 2.0 / 2.5, 0.02);
}

TEST(SafetySupervisorTest, StopsWhenEstimatesStopComingOrGrowUncertain) {
  SafetySupervisor blackout;
  Drive(&blackout, 0.0, 5.0, 2.78, Tracking);
  double stopped_at = -1.0;
  Drive(
      &blackout, 5.0, 10.0, 2.78, [](SafetySupervisor*, double) {}, &stopped_at);
  // The last estimate at 4.8 s is too old from 5.4 s on; then 1.11 s of braking.
  EXPECT_NEAR(stopped_at, 4.8 + 0.6 + 2.78 / 2.5, 0.03);

  SafetySupervisor uncertain;
  Drive(&uncertain, 0.0, 5.0, 2.78, Tracking);
  EXPECT_GT(Drive(&uncertain, 5.0, 6.0, 2.78,
                  [](SafetySupervisor* e, double t) {
                    e->OnEstimate(FromSeconds(t), true,
                                  Eigen::Matrix2d::Identity() * 0.2);  // 0.45 m
                  }),
            2.7);
  EXPECT_EQ(Drive(&uncertain, 6.0, 8.0, 2.78,
                  [](SafetySupervisor* e, double t) {
                    e->OnEstimate(FromSeconds(t), true,
                                  Eigen::Matrix2d::Identity() * 0.3);  // 0.55 m
                  }),
            0.0);
}

TEST(SafetySupervisorTest, ABriefLossStillEndsInAFullStop) {
  SafetySupervisor s;
  Drive(&s, 0.0, 10.0, 2.78, Tracking);
  double stopped_at = -1.0;
  // One lost estimate at 10.0 s, tracking again from 10.2 s.
  Drive(
      &s, 10.0, 14.0, 2.78,
      [](SafetySupervisor* e, double t) { e->OnEstimate(FromSeconds(t), t > 10.1, kSmall); },
      &stopped_at);
  EXPECT_NEAR(stopped_at, 10.0 + 2.78 / 2.5, 0.02);
  EXPECT_EQ(s.interventions(), 1);
}

TEST(SafetySupervisorTest, FramesThatRejectEverythingStopTheCar) {
  SafetySupervisor s;
  Drive(&s, 0.0, 10.0, 2.78, Tracking);
  double stopped_at = -1.0;
  // From 10 s every frame rejects its 4 observations; the third (10.4 s)
  // makes it unhealthy.
  Drive(
      &s, 10.0, 14.0, 2.78,
      [](SafetySupervisor* e, double t) { e->OnEstimate(FromSeconds(t), true, kSmall, 0, 4); },
      &stopped_at);
  EXPECT_NEAR(stopped_at, 10.4 + 2.78 / 2.5, 0.02);
  // Two such frames alone do not.
  SafetySupervisor two;
  Drive(&two, 0.0, 10.0, 2.78, [](SafetySupervisor* e, double t) {
    const bool bad = t >= 5.0 && t < 5.3;
    e->OnEstimate(FromSeconds(t), true, kSmall, bad ? 0 : 3, bad ? 2 : 0);
  });
  EXPECT_EQ(two.interventions(), 0);
}

// Found in closed loop: stopped where the only landmark in view disagrees
// with the map (rejected now and then, nothing else used), the car stood
// for ever although localization tracked with a small covariance.
TEST(SafetySupervisorTest, RejectionsSeenWhileHeldStillDoNotKeepTheCarStanding) {
  SafetySupervisor s;
  Drive(&s, 0.0, 10.0, 2.78, Tracking);
  // From 10 s: nothing used; every other frame rejects one observation.
  int frame = 0;
  double fastest_after_stop = 0.0;
  bool stopped = false;
  for (int k = 1000; k < 2000; ++k) {
    const double t = k / 100.0;
    if (k % 20 == 0) s.OnEstimate(FromSeconds(t), true, kSmall, 0, (frame++ % 2 == 0) ? 1 : 0);
    const double v = s.AllowedSpeed(FromSeconds(t), 0.01, 2.78, INFINITY);
    stopped = stopped || v == 0.0;
    if (stopped) fastest_after_stop = std::max(fastest_after_stop, v);
  }
  // It stops, goes on after resume_after_s, and the next three rejections
  // (1.2 s at 1 m/s^2) stop it again before it is fast: it creeps on
  // instead of standing for ever.
  EXPECT_TRUE(stopped);
  EXPECT_GT(s.interventions(), 1);
  EXPECT_GT(fastest_after_stop, 0.0);
  EXPECT_LE(fastest_after_stop, 1.25);
}

TEST(SafetySupervisorTest, InvalidOptionsThrow) {
  SafetyOptions o;
  o.brake_decel_mps2 = 0.0;
  EXPECT_THROW(SafetySupervisor{o}, std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::control
