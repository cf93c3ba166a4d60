#include "parkslam/odometry/odometry_ekf.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "parkslam/common/angles.h"
#include "parkslam/common/field_checker.h"

namespace parkslam::odometry {
namespace {

using RowVector = Eigen::Matrix<double, 1, OdometryEkf::kStateSize>;

double Square(double x) { return x * x; }

}  // namespace

bool OdometryEkfOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.Part(vehicle, "vehicle");
  const std::pair<const char*, double> sigmas[] = {
      {"wheel_speed_sigma_mps", wheel_speed_sigma_mps},
      {"steering_wheel_sigma_rad", steering_wheel_sigma_rad},
      {"steering_model_sigma_radps", steering_model_sigma_radps},
      {"gyro_sigma_radps", gyro_sigma_radps},
      {"heading_sigma_rad", heading_sigma_rad},
      {"accel_sigma_mps2_per_sqrt_hz", accel_sigma_mps2_per_sqrt_hz},
      {"yaw_accel_sigma_radps2_per_sqrt_hz", yaw_accel_sigma_radps2_per_sqrt_hz},
      {"gyro_bias_walk_radps_per_sqrt_s", gyro_bias_walk_radps_per_sqrt_s},
      {"heading_bias_walk_rad_per_sqrt_s", heading_bias_walk_rad_per_sqrt_s},
      {"initial_position_sigma_m", initial_position_sigma_m},
      {"initial_speed_sigma_mps", initial_speed_sigma_mps},
      {"initial_yaw_rate_sigma_radps", initial_yaw_rate_sigma_radps},
      {"gyro_bias_sigma_radps", gyro_bias_sigma_radps},
      {"heading_bias_sigma_rad", heading_bias_sigma_rad},
      {"wheel_scale_sigma", wheel_scale_sigma},
      {"heading_disturbance_sigma_rad", heading_disturbance_sigma_rad},
      {"jerk_sigma_mps3_per_sqrt_hz", jerk_sigma_mps3_per_sqrt_hz},
      {"yaw_jerk_sigma_radps3_per_sqrt_hz", yaw_jerk_sigma_radps3_per_sqrt_hz},
      {"initial_accel_sigma_mps2", initial_accel_sigma_mps2},
      {"initial_yaw_accel_sigma_radps2", initial_yaw_accel_sigma_radps2}};
  for (const auto& [name, sigma] : sigmas) c.NonNegative(sigma, name);
  c.Positive(heading_disturbance_length_m, "heading_disturbance_length_m");
  c.Positive(innovation_gate_chi2, "innovation_gate_chi2");
  c.NonNegative(gate_after_s, "gate_after_s");
  c.NonNegative(fault_reset_after_s, "fault_reset_after_s");
  // Measurements need noise, or their updates divide by zero.
  c.Positive(wheel_speed_sigma_mps, "wheel_speed_sigma_mps");
  c.Positive(gyro_sigma_radps, "gyro_sigma_radps");
  c.Positive(heading_sigma_rad, "heading_sigma_rad");
  c.Require(steering_wheel_sigma_rad + steering_model_sigma_radps > 0, "steering_wheel_sigma_rad",
            "and steering_model_sigma_radps must not both be zero");
  return c.ok();
}

const char* OdometryEkfStats::ChannelName(int channel) {
  static const char* const kNames[kChannels] = {"wheel_speed", "steering", "gyro", "heading"};
  return channel >= 0 && channel < kChannels ? kNames[channel] : "?";
}

OdometryEkf::OdometryEkf(const OdometryEkfOptions& options) : options_(options) {}

void OdometryEkf::Initialize(TimeNs t_ns, const SE2& T_map_vehicle, double yaw_sigma_rad) {
  t_ns_ = t_ns;
  initialized_at_ns_ = t_ns;
  x_.setZero();
  x_[kX] = T_map_vehicle.x();
  x_[kY] = T_map_vehicle.y();
  x_[kYaw] = T_map_vehicle.yaw();
  const OdometryEkfOptions& o = options_;
  StateVector sigma = StateVector::Zero();
  sigma.head<kCloneX>() << o.initial_position_sigma_m, o.initial_position_sigma_m, yaw_sigma_rad,
      o.initial_speed_sigma_mps, o.initial_yaw_rate_sigma_radps, o.gyro_bias_sigma_radps,
      o.heading_bias_sigma_rad, o.wheel_scale_sigma, o.heading_disturbance_sigma_rad,
      o.initial_accel_sigma_mps2, o.initial_yaw_accel_sigma_radps2;
  P_.setZero();
  P_.topLeftCorner<kCloneX, kCloneX>() = sigma.head<kCloneX>().cwiseAbs2().asDiagonal();
  initialized_ = true;
  ClonePose();
}

void OdometryEkf::InitializeFromHeading(TimeNs t_ns, const Eigen::Vector2d& p_map,
                                        std::optional<double> heading_rad) {
  const OdometryEkfOptions& o = options_;
  if (!heading_rad) {
    Initialize(t_ns, SE2(p_map, 0.0), 0.0);
    return;
  }
  Initialize(t_ns, SE2(p_map, *heading_rad),
             std::sqrt(Square(o.heading_bias_sigma_rad) + Square(o.heading_disturbance_sigma_rad) +
                       Square(o.heading_sigma_rad)));
  // yaw = heading - b_h - d - noise: the yaw error is minus the bias and
  // disturbance errors plus the heading noise, so they are correlated.
  P_(kYaw, kHeadingBias) = P_(kHeadingBias, kYaw) = -Square(o.heading_bias_sigma_rad);
  P_(kYaw, kHeadingDisturbance) = P_(kHeadingDisturbance, kYaw) =
      -Square(o.heading_disturbance_sigma_rad);
  ClonePose();
}

void OdometryEkf::ClonePose() {
  x_.segment<3>(kCloneX) = x_.head<3>();
  // The clone equals the pose: same rows and columns, same block.
  P_.block<3, kStateSize>(kCloneX, 0) = P_.block<3, kStateSize>(kX, 0);
  P_.block<kStateSize, 3>(0, kCloneX) = P_.block<kStateSize, 3>(0, kX);
  P_.block<3, 3>(kCloneX, kCloneX) = P_.block<3, 3>(kX, kX);
}

OdometryEkf::RelativeMotion OdometryEkf::MotionSinceClone() const {
  // delta_t = R(yaw_c)^T (t - t_c), delta_yaw = yaw - yaw_c; J over
  // (clone x, y, yaw, pose x, y, yaw).
  const double c = std::cos(x_[kCloneYaw]), s = std::sin(x_[kCloneYaw]);
  const Eigen::Vector2d d = x_.head<2>() - x_.segment<2>(kCloneX);
  Eigen::Matrix<double, 3, 6> J = Eigen::Matrix<double, 3, 6>::Zero();
  J.block<2, 2>(0, 0) << -c, -s, s, -c;
  J(0, 2) = -s * d.x() + c * d.y();
  J(1, 2) = -c * d.x() - s * d.y();
  J.block<2, 2>(0, 3) << c, s, -s, c;
  J(2, 2) = -1.0;
  J(2, 5) = 1.0;
  Eigen::Matrix<double, 6, 6> P_sub;
  P_sub << P_.block<3, 3>(kCloneX, kCloneX), P_.block<3, 3>(kCloneX, kX),
      P_.block<3, 3>(kX, kCloneX), P_.block<3, 3>(kX, kX);
  RelativeMotion motion;
  motion.T_clone_now = SE2(x_[kCloneX], x_[kCloneY], x_[kCloneYaw]).inverse() * pose();
  motion.covariance = J * P_sub * J.transpose();
  motion.covariance = 0.5 * (motion.covariance + motion.covariance.transpose()).eval();
  return motion;
}

void OdometryEkf::Predict(double dt_s) {
  if (dt_s <= 0.0) return;
  const double yaw = x_[kYaw], v = x_[kSpeed], omega = x_[kYawRate];
  const double a = x_[kAccel], alpha = x_[kYawAccel];
  const double dt2 = dt_s * dt_s;
  const double ds = v * dt_s + 0.5 * a * dt2;
  const double dyaw = omega * dt_s + 0.5 * alpha * dt2;
  // The step moves along the heading at its middle: in a turn the heading
  // at the step's start would put every step, and so the whole arc, to the
  // outside by v omega dt / 2 per second, a bias the covariance never held.
  const double c = std::cos(yaw + 0.5 * dyaw), s = std::sin(yaw + 0.5 * dyaw);
  x_[kX] += ds * c;
  x_[kY] += ds * s;
  x_[kYaw] = NormalizeAngle(yaw + dyaw);
  x_[kSpeed] += a * dt_s;
  x_[kYawRate] += alpha * dt_s;

  // F = d(next state)/d(state); d(yaw + dyaw / 2) / d(omega) = dt / 2 and
  // / d(alpha) = dt^2 / 4.
  StateMatrix F = StateMatrix::Identity();
  F(kX, kYaw) = -ds * s;
  F(kX, kSpeed) = c * dt_s;
  F(kX, kAccel) = 0.5 * c * dt2;
  F(kX, kYawRate) = -0.5 * ds * s * dt_s;
  F(kX, kYawAccel) = -0.25 * ds * s * dt2;
  F(kY, kYaw) = ds * c;
  F(kY, kSpeed) = s * dt_s;
  F(kY, kAccel) = 0.5 * s * dt2;
  F(kY, kYawRate) = 0.5 * ds * c * dt_s;
  F(kY, kYawAccel) = 0.25 * ds * c * dt2;
  F(kYaw, kYawRate) = dt_s;
  F(kYaw, kYawAccel) = 0.5 * dt2;
  F(kSpeed, kAccel) = dt_s;
  F(kYawRate, kYawAccel) = dt_s;

  const OdometryEkfOptions& o = options_;
  StateMatrix Q = StateMatrix::Zero();
  // The compass's disturbance: Gauss-Markov in the distance driven.
  const double phi = std::exp(-std::abs(v) * dt_s / o.heading_disturbance_length_m);
  F(kHeadingDisturbance, kHeadingDisturbance) = phi;
  x_[kHeadingDisturbance] *= phi;
  Q(kHeadingDisturbance, kHeadingDisturbance) =
      (1.0 - phi * phi) * Square(o.heading_disturbance_sigma_rad);
  Q(kSpeed, kSpeed) = Square(o.accel_sigma_mps2_per_sqrt_hz) * dt_s;
  Q(kYawRate, kYawRate) = Square(o.yaw_accel_sigma_radps2_per_sqrt_hz) * dt_s;
  // White jerk q on (rate, acceleration): q [dt^3 / 3, dt^2 / 2; dt^2 / 2, dt].
  auto add_jerk = [&](int rate, int accel, double q) {
    Q(rate, rate) += q * dt2 * dt_s / 3.0;
    Q(rate, accel) = Q(accel, rate) = q * dt2 / 2.0;
    Q(accel, accel) = q * dt_s;
  };
  add_jerk(kSpeed, kAccel, Square(o.jerk_sigma_mps3_per_sqrt_hz));
  add_jerk(kYawRate, kYawAccel, Square(o.yaw_jerk_sigma_radps3_per_sqrt_hz));
  Q(kGyroBias, kGyroBias) = Square(o.gyro_bias_walk_radps_per_sqrt_s) * dt_s;
  Q(kHeadingBias, kHeadingBias) = Square(o.heading_bias_walk_rad_per_sqrt_s) * dt_s;
  P_ = F * P_ * F.transpose() + Q;
  P_ = 0.5 * (P_ + P_.transpose());
}

void OdometryEkf::PredictTo(TimeNs t_ns) {
  if (t_ns <= t_ns_) return;
  Predict(ToSeconds(t_ns - t_ns_));
  t_ns_ = t_ns;
}

void OdometryEkf::Update(double innovation, const RowVector& h, double r, const StateVector& Ph,
                         double s) {
  const StateVector k = Ph / s;
  x_ += k * innovation;
  x_[kYaw] = NormalizeAngle(x_[kYaw]);
  // Joseph form keeps P symmetric and positive definite.
  const StateMatrix i_kh = StateMatrix::Identity() - k * h;
  P_ = i_kh * P_ * i_kh.transpose() + k * r * k.transpose();
}

void OdometryEkf::GatedUpdate(int channel, double innovation, const RowVector& h, double r,
                              int reset_state, double reset_sigma) {
  const OdometryEkfOptions& o = options_;
  const bool gating = ToSeconds(t_ns_ - initialized_at_ns_) >= o.gate_after_s;
  StateVector Ph = P_ * h.transpose();
  double s = h.dot(Ph) + r;
  if (!gating || innovation * innovation <= o.innovation_gate_chi2 * s) {
    rejecting_since_ns_[channel] = -1;
    Update(innovation, h, r, Ph, s);
    return;
  }
  if (rejecting_since_ns_[channel] < 0) rejecting_since_ns_[channel] = t_ns_;
  if (ToSeconds(t_ns_ - rejecting_since_ns_[channel]) < o.fault_reset_after_s) {
    ++stats_.rejected[channel];
    return;
  }
  // The sensor has moved to a new level: give the state that explains it
  // its prior uncertainty back, or the step's size if larger (dropping its
  // correlations), and take the measurement; the state takes the step.
  const double kept = P_(reset_state, reset_state);
  P_.row(reset_state).setZero();
  P_.col(reset_state).setZero();
  P_(reset_state, reset_state) = std::max(
      {kept, Square(reset_sigma), Square(innovation / std::max(std::abs(h[reset_state]), 1e-9))});
  ++stats_.resets[channel];
  rejecting_since_ns_[channel] = -1;
  Ph = P_ * h.transpose();
  s = h.dot(Ph) + r;
  Update(innovation, h, r, Ph, s);
}

void OdometryEkf::NoteSample(int channel) {
  if (last_sample_ns_[channel] >= 0) {
    stats_.longest_gap_s[channel] =
        std::max(stats_.longest_gap_s[channel], ToSeconds(t_ns_ - last_sample_ns_[channel]));
  }
  last_sample_ns_[channel] = t_ns_;
}

void OdometryEkf::UpdateWheelSpeed(const WheelSpeed& m) {
  RowVector h = RowVector::Zero();
  h[kSpeed] = 1.0 + x_[kWheelScale];
  h[kWheelScale] = x_[kSpeed];
  NoteSample(OdometryEkfStats::kWheelSpeed);
  GatedUpdate(OdometryEkfStats::kWheelSpeed, m.speed_mps - (1.0 + x_[kWheelScale]) * x_[kSpeed], h,
              Square(options_.wheel_speed_sigma_mps), kSpeed, options_.initial_speed_sigma_mps);
}

void OdometryEkf::UpdateSteering(const SteeringAngle& m) {
  const VehicleParameters& vehicle = options_.vehicle;
  const double delta = m.steering_wheel_rad / vehicle.steering_ratio;
  const double tan_delta = std::tan(delta);
  const double v = x_[kSpeed];
  RowVector h = RowVector::Zero();
  h[kYawRate] = 1.0;
  h[kSpeed] = -tan_delta / vehicle.wheelbase_m;
  // d(v tan(delta) / L)/d(steering) = v / (L ratio cos^2(delta)).
  const double d_omega =
      v / (vehicle.wheelbase_m * vehicle.steering_ratio * Square(std::cos(delta)));
  const double r = Square(d_omega * options_.steering_wheel_sigma_rad) +
                   Square(options_.steering_model_sigma_radps);
  NoteSample(OdometryEkfStats::kSteering);
  GatedUpdate(OdometryEkfStats::kSteering,
              0.0 - (x_[kYawRate] - v * tan_delta / vehicle.wheelbase_m), h, r, kYawRate,
              options_.initial_yaw_rate_sigma_radps);
}

void OdometryEkf::UpdateImu(const ImuSample& m) {
  RowVector h = RowVector::Zero();
  h[kYawRate] = 1.0;
  h[kGyroBias] = 1.0;
  NoteSample(OdometryEkfStats::kGyro);
  GatedUpdate(OdometryEkfStats::kGyro, m.yaw_rate_radps - (x_[kYawRate] + x_[kGyroBias]), h,
              Square(options_.gyro_sigma_radps), kGyroBias, options_.gyro_bias_sigma_radps);
  if (!m.heading_rad) return;  // a gyro-only IMU: the yaw rate alone
  h.setZero();
  h[kYaw] = 1.0;
  h[kHeadingBias] = 1.0;
  h[kHeadingDisturbance] = 1.0;
  // A heading jump is the AHRS's offset changing: the heading bias takes it.
  GatedUpdate(OdometryEkfStats::kHeading,
              AngleDiff(*m.heading_rad, x_[kYaw] + x_[kHeadingBias] + x_[kHeadingDisturbance]), h,
              Square(options_.heading_sigma_rad), kHeadingBias, options_.heading_bias_sigma_rad);
}

bool OdometryEkf::Process(const SensorEvent& event) {
  const TimeNs t = EventTime(event);
  if (!initialized_) return false;
  if (t < t_ns_) {
    ++stats_.late_events;
    return false;
  }
  PredictTo(t);
  if (const auto* w = std::get_if<WheelSpeed>(&event)) {
    UpdateWheelSpeed(*w);
  } else if (const auto* st = std::get_if<SteeringAngle>(&event)) {
    UpdateSteering(*st);
  } else if (const auto* imu = std::get_if<ImuSample>(&event)) {
    UpdateImu(*imu);
  }
  return true;
}

OdometryEkfOptions EkfOptionsFromSpec(const OdometrySensorSpec& spec,
                                      const VehicleParameters& vehicle) {
  OdometryEkfOptions o;
  o.vehicle = vehicle;
  o.wheel_speed_sigma_mps = spec.wheel_speed_sigma_mps;
  o.steering_wheel_sigma_rad = spec.steering_wheel_sigma_rad;
  o.gyro_sigma_radps = spec.gyro_sigma_radps;
  o.heading_sigma_rad = spec.heading_sigma_rad;
  o.gyro_bias_walk_radps_per_sqrt_s = spec.gyro_bias_walk_radps_per_sqrt_s;
  o.heading_bias_walk_rad_per_sqrt_s = spec.heading_bias_walk_rad_per_sqrt_s;
  o.gyro_bias_sigma_radps = spec.gyro_bias_sigma_radps;
  o.heading_bias_sigma_rad = spec.heading_bias_sigma_rad;
  o.wheel_scale_sigma = spec.wheel_speed_scale_sigma;
  return o;
}

}  // namespace parkslam::odometry
