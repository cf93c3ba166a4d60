#ifndef PARKSLAM_ODOMETRY_ODOMETRY_EKF_H_
#define PARKSLAM_ODOMETRY_ODOMETRY_EKF_H_

// Kalman dead reckoning from wheel speed, steering angle and a cheap IMU
// (paper III-C: "a Kalman-based extrapolation with the steering wheel, car
// speed and the compass readings from a cheap IMU").
//
// State x (14): [x_m, y_m, yaw_rad, v_mps, omega_radps, gyro_bias_radps,
//                heading_bias_rad, wheel_scale_error, heading_disturbance_rad,
//                a_mps2, alpha_radps2,
//                clone_x_m, clone_y_m, clone_yaw_rad]
// The last three are a stochastic clone of the pose at the last keyframe
// (Roumeliotis and Burdick, "Stochastic cloning", ICRA 2002): they stay fixed
// in prediction but keep their cross-covariance with the moving pose, so the
// motion since the keyframe comes with its own covariance (RelativeMotion()).
// Process (constant acceleration a and yaw acceleration alpha over dt):
//   ds = v dt + a dt^2 / 2,  dyaw = omega dt + alpha dt^2 / 2,
//   x += ds cos(yaw + dyaw / 2),  y += ds sin(yaw + dyaw / 2),
//   yaw += dyaw,  v += a dt,  omega += alpha dt,
//   a, alpha: random walks (white jerk), v and omega: also a white
//   acceleration; biases: random walks; scale: constant.
// A car speeds up, brakes and steers into turns over seconds; a filter whose
// speed and yaw rate were random walks would lag them by its gain's delay,
// and the lag, the same sign for the whole manoeuvre, is an error the
// covariance never holds (docs/odometry.md, "Motion over a window").
// Measurements:
//   wheel speed      z = (1 + s) v                         (R = sigma_w^2)
//   steering angle   0 = omega - v tan(z_sw / ratio) / L   (bicycle model)
//   gyroscope        z = omega + b_g                       (R = sigma_g^2)
//   AHRS heading     z = yaw + b_h + d                     (R = sigma_h^2)
//   (no heading: a gyro-only IMU, the yaw from the gyro alone)
//
// Indoors the compass is bent near steel by several degrees, by an amount
// that depends on the place (sim/compass_field.h). The disturbance d is a
// first-order Gauss-Markov process in the distance driven s, with
// correlation length L and stationary spread sigma_d:
//   d(s + ds) = phi d(s) + w,  phi = exp(-ds / L),  var(w) = (1 - phi^2) sigma_d^2.
// So over a few metres the yaw follows the gyro, and the compass bounds its
// drift only over tens of metres; standing still, nothing changes. The
// AHRS's own bias b_h stays a random walk, so a lasting offset is still
// learnt. A compass that disagrees with the gyro beyond that is gated
// (below).
//
// Faults (docs/robustness.md): each scalar update is gated on its
// normalized innovation squared, y^2 / (h P h^T + r) > innovation_gate_chi2
// (1 degree of freedom), so a single spike of the gyroscope, the heading or
// the wheel speed is rejected. A sensor that keeps failing the gate for
// fault_reset_after_s has changed rather than spiked: its bias state (the
// heading bias for a heading jump, the gyro bias, the speed, the yaw rate
// for steering) gets its prior variance back (at least the step's square)
// and the measurement is taken, so the filter follows the new level instead
// of rejecting it for ever.

#include <Eigen/Core>
#include <optional>
#include <string>

#include "parkslam/common/se2.h"
#include "parkslam/common/time.h"
#include "parkslam/sensor/odometry_spec.h"
#include "parkslam/sensor/sensor_data.h"
#include "parkslam/sensor/vehicle.h"

namespace parkslam::odometry {

struct OdometryEkfOptions {
  VehicleParameters vehicle;
  // Measurement noise (standard deviations).
  double wheel_speed_sigma_mps = 0.02;
  double steering_wheel_sigma_rad = 0.01;
  // Slip beyond the bicycle model, and the steering's sample lagging the
  // yaw rate it sets while the wheel turns (docs/odometry.md).
  double steering_model_sigma_radps = 0.002;
  double gyro_sigma_radps = 0.005;
  double heading_sigma_rad = 0.01;
  // Process noise (random-walk densities). Chosen by Monte-Carlo NEES on the
  // default drive, of the pose since the start and of the motion over 1 and
  // 5 s windows (docs/odometry.md, "Consistency").
  double accel_sigma_mps2_per_sqrt_hz = 0.1;
  double yaw_accel_sigma_radps2_per_sqrt_hz = 0.03;
  // White jerk on the acceleration states; 0 with zero initial sigmas keeps
  // them at 0 (the constant-speed, constant-yaw-rate model).
  double jerk_sigma_mps3_per_sqrt_hz = 1.0;
  double yaw_jerk_sigma_radps3_per_sqrt_hz = 0.5;
  double gyro_bias_walk_radps_per_sqrt_s = 0.00005;
  double heading_bias_walk_rad_per_sqrt_s = 0.0005;
  // The compass's disturbance near steel (above); sigma 0 models a compass
  // that nothing disturbs (the bias walk alone).
  double heading_disturbance_sigma_rad = 0.08;
  double heading_disturbance_length_m = 3.0;
  // Prior standard deviations at initialization.
  double initial_position_sigma_m = 1e-3;
  double initial_speed_sigma_mps = 0.5;
  double initial_yaw_rate_sigma_radps = 0.2;
  double gyro_bias_sigma_radps = 0.003;
  double heading_bias_sigma_rad = 0.02;
  double wheel_scale_sigma = 0.003;
  double initial_accel_sigma_mps2 = 0.5;
  double initial_yaw_accel_sigma_radps2 = 0.3;
  // Fault gating (above). 19.5 is the chi-square quantile of p = 1e-5 with
  // one degree of freedom; gating starts gate_after_s after initialization,
  // when the priors have converged.
  double innovation_gate_chi2 = 19.5;
  double gate_after_s = 2.0;
  double fault_reset_after_s = 1.0;

  bool IsValid(std::string* error) const;
};

// The filter tuned from the sensors' datasheet (a dataset's
// sensors.odometry section) and the vehicle.
OdometryEkfOptions EkfOptionsFromSpec(const OdometrySensorSpec& spec,
                                      const VehicleParameters& vehicle);

// What the filter saw of its inputs' faults.
struct OdometryEkfStats {
  enum Channel { kWheelSpeed = 0, kSteering, kGyro, kHeading, kChannels };
  static const char* ChannelName(int channel);
  int late_events = 0;           // older than the filter's time: dropped
  int rejected[kChannels] = {};  // updates refused by the gate
  int resets[kChannels] = {};    // faults accepted as a new level
  // The longest time between two samples of a sensor (wheel speed,
  // steering, IMU), in seconds.
  double longest_gap_s[kChannels] = {};
};

class OdometryEkf {
 public:
  static constexpr int kStateSize = 14;
  using StateVector = Eigen::Matrix<double, kStateSize, 1>;
  using StateMatrix = Eigen::Matrix<double, kStateSize, kStateSize>;
  enum Index {
    kX = 0,
    kY,
    kYaw,
    kSpeed,
    kYawRate,
    kGyroBias,
    kHeadingBias,
    kWheelScale,
    kHeadingDisturbance,
    kAccel,
    kYawAccel,
    kCloneX,
    kCloneY,
    kCloneYaw
  };

  // The motion from the cloned keyframe pose to the current pose,
  // T_clone_now, with the covariance of (dx_m, dy_m, dyaw_rad).
  struct RelativeMotion {
    SE2 T_clone_now;
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  };

  explicit OdometryEkf(const OdometryEkfOptions& options);

  // Starts the filter at t_ns with a known pose; yaw_sigma_rad is the
  // uncertainty of its yaw.
  void Initialize(TimeNs t_ns, const SE2& T_map_vehicle, double yaw_sigma_rad);
  // Starts the filter at t_ns at a known position with the yaw read from the
  // AHRS heading, whose error is the heading bias plus its noise. Without a
  // heading (a gyro-only IMU) the start's yaw is 0 and exact: the map frame
  // is then the car's frame at the start.
  void InitializeFromHeading(TimeNs t_ns, const Eigen::Vector2d& p_map,
                             std::optional<double> heading_rad);
  bool initialized() const { return initialized_; }

  // Predicts to the event's time and applies it. Slot and tag frames are
  // ignored here. Events older than the filter time are rejected (false).
  bool Process(const SensorEvent& event);

  // Propagates the state to t_ns without a measurement.
  void PredictTo(TimeNs t_ns);

  // Starts a new keyframe: the clone takes the current pose.
  void ClonePose();
  RelativeMotion MotionSinceClone() const;

  TimeNs time_ns() const { return t_ns_; }
  SE2 pose() const { return SE2(x_[kX], x_[kY], x_[kYaw]); }
  // Covariance of (x_m, y_m, yaw_rad).
  Eigen::Matrix3d pose_covariance() const { return P_.topLeftCorner<3, 3>(); }
  const StateVector& state() const { return x_; }
  const StateMatrix& covariance() const { return P_; }
  const OdometryEkfStats& stats() const { return stats_; }

 private:
  void Predict(double dt_s);
  // Scalar update: innovation y, Jacobian row h, variance r, with Ph = P h^T
  // and s = h P h^T + r as the gate computed them.
  void Update(double innovation, const Eigen::Matrix<double, 1, kStateSize>& h, double r,
              const StateVector& Ph, double s);
  // Update through the fault gate of `channel`; `reset_state` is the state
  // whose prior variance `reset_sigma` comes back when the fault persists.
  void GatedUpdate(int channel, double innovation, const Eigen::Matrix<double, 1, kStateSize>& h,
                   double r, int reset_state, double reset_sigma);
  void NoteSample(int channel);
  void UpdateWheelSpeed(const WheelSpeed& m);
  void UpdateSteering(const SteeringAngle& m);
  void UpdateImu(const ImuSample& m);

  OdometryEkfOptions options_;
  bool initialized_ = false;
  TimeNs t_ns_ = 0;
  StateVector x_ = StateVector::Zero();
  StateMatrix P_ = StateMatrix::Identity();
  TimeNs initialized_at_ns_ = 0;
  // Per channel: the time of the last sample and since when the gate has
  // rejected it (-1: it is passing).
  TimeNs last_sample_ns_[OdometryEkfStats::kChannels] = {-1, -1, -1, -1};
  TimeNs rejecting_since_ns_[OdometryEkfStats::kChannels] = {-1, -1, -1, -1};
  OdometryEkfStats stats_;
};

}  // namespace parkslam::odometry

#endif  // PARKSLAM_ODOMETRY_ODOMETRY_EKF_H_
