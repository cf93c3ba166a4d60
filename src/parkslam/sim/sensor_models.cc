#include "parkslam/sim/sensor_models.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "parkslam/common/angles.h"

namespace parkslam::sim {
namespace {

// The state at time t: the nearest sample of the ground truth (which runs at
// a higher rate than any sensor).
const VehicleState& StateAt(const std::vector<VehicleState>& states, TimeNs t_ns) {
  const auto it = std::lower_bound(states.begin(), states.end(), t_ns,
                                   [](const VehicleState& s, TimeNs t) { return s.t_ns < t; });
  if (it == states.end()) return states.back();
  if (it != states.begin() && (t_ns - (it - 1)->t_ns) < (it->t_ns - t_ns)) return *(it - 1);
  return *it;
}

std::vector<TimeNs> SampleTimes(const std::vector<VehicleState>& states, double rate_hz,
                                TimeNs offset_ns = 0) {
  std::vector<TimeNs> times;
  const TimeNs end = states.back().t_ns;
  const double period_s = 1.0 / rate_hz;
  for (long k = 0;; ++k) {
    const TimeNs t = states.front().t_ns + offset_ns + FromSeconds(k * period_s);
    if (t > end) break;
    times.push_back(t);
  }
  return times;
}

DigitReading CorrectDigit(char digit, Random& rng) {
  DigitReading reading;
  const double p = rng.Uniform(0.75, 0.99);
  reading.hypotheses.push_back({digit, p});
  const std::string& partners = ConfusableDigits(digit);
  if (rng.Bernoulli(0.5)) {
    reading.hypotheses.push_back(
        {partners[rng.Index(partners.size())], rng.Uniform(0.2, 0.9) * (1.0 - p)});
  }
  return reading;
}

DigitReading ConfusedDigit(char digit, const IdSensorConfig& config, Random& rng) {
  const std::string& partners = ConfusableDigits(digit);
  const char wrong = partners[rng.Index(partners.size())];
  const double p = rng.Uniform(0.5, 0.9);
  DigitReading reading;
  reading.hypotheses.push_back({wrong, p});
  char second = digit;
  if (!rng.Bernoulli(config.true_digit_second_rate)) {
    // Any digit but the true and the wrong one.
    do {
      second = static_cast<char>('0' + rng.Index(10));
    } while (second == digit || second == wrong);
  }
  reading.hypotheses.push_back({second, rng.Uniform(0.3, 0.9) * (1.0 - p)});
  return reading;
}

Eigen::Vector2d Rotate(const Eigen::Vector2d& v, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

struct TopView {
  Eigen::Vector2d center_vehicle;
  double half_length_m, half_width_m;

  bool Contains(const Eigen::Vector2d& p_vehicle) const {
    const Eigen::Vector2d d = p_vehicle - center_vehicle;
    return std::abs(d.x()) <= half_length_m && std::abs(d.y()) <= half_width_m;
  }
};

// The detector's slot: entrance corners seen with noise; far corners seen
// when in view (sometimes), otherwise guessed along the side direction at a
// standard depth.
SlotObservation ObserveSlot(const std::array<Eigen::Vector2d, 4>& corners_vehicle,
                            const TopView& view, const SlotSensorConfig& config, Random& rng) {
  SlotObservation obs;
  auto sigma_at = [&](const Eigen::Vector2d& p) {
    return config.corner_sigma_m + config.corner_sigma_per_m * (p - view.center_vehicle).norm();
  };
  const double sigma = std::max(sigma_at(corners_vehicle[0]), sigma_at(corners_vehicle[1]));
  obs.corner_sigma_m = sigma;
  for (int i = 0; i < 2; ++i) {
    obs.corners_vehicle[i] =
        corners_vehicle[i] + Eigen::Vector2d(rng.Gaussian(sigma), rng.Gaussian(sigma));
  }
  const bool far_in_view = view.Contains(corners_vehicle[2]) && view.Contains(corners_vehicle[3]);
  const bool far_seen = far_in_view && rng.Bernoulli(config.far_corner_observed_rate);
  if (far_seen) {
    for (int i = 2; i < 4; ++i) {
      obs.corners_vehicle[i] =
          corners_vehicle[i] + Eigen::Vector2d(rng.Gaussian(sigma), rng.Gaussian(sigma));
      obs.corner_observed[i] = true;
    }
  } else {
    const double entrance_m = (obs.corners_vehicle[1] - obs.corners_vehicle[0]).norm();
    const double depth_m = entrance_m > config.parallel_min_entrance_m ? config.parallel_depth_m
                                                                       : config.standard_depth_m;
    const Eigen::Vector2d side = Rotate((corners_vehicle[3] - corners_vehicle[0]).normalized(),
                                        rng.Gaussian(DegToRad(config.far_direction_sigma_deg)));
    obs.corners_vehicle[3] = obs.corners_vehicle[0] + depth_m * side;
    obs.corners_vehicle[2] = obs.corners_vehicle[1] + depth_m * side;
    obs.corner_observed[2] = obs.corner_observed[3] = false;
  }
  return obs;
}

SlotObservation FalseSlot(const TopView& view, const SensorConfig& config, Random& rng) {
  const Eigen::Vector2d c0 =
      view.center_vehicle + Eigen::Vector2d(rng.Uniform(-view.half_length_m, view.half_length_m),
                                            rng.Uniform(-view.half_width_m, view.half_width_m));
  const double yaw = rng.Uniform(-kPi, kPi);
  const Eigen::Vector2d along(std::cos(yaw), std::sin(yaw));
  const Eigen::Vector2d left(-along.y(), along.x());
  const double width_m = rng.Uniform(2.2, 2.8), depth_m = config.slots.standard_depth_m;
  std::array<Eigen::Vector2d, 4> corners{
      c0, c0 + width_m * along, c0 + width_m * along + depth_m * left, c0 + depth_m * left};
  SlotObservation obs = ObserveSlot(corners, view, config.slots, rng);
  obs.detection_confidence = rng.Uniform(0.3, 0.8);
  if (rng.Bernoulli(0.5)) {
    const std::string random_id{static_cast<char>('0' + rng.Index(10)),
                                static_cast<char>('0' + rng.Index(10))};
    obs.id = SimulateIdReading(random_id, config.ids, rng);
  }
  return obs;
}

}  // namespace

const std::string& ConfusableDigits(char digit) {
  static const std::string kPartners[10] = {"86", "7", "7", "8", "9", "6", "58", "12", "306", "4"};
  static const std::string kNone = "8";
  if (digit < '0' || digit > '9') return kNone;
  return kPartners[digit - '0'];
}

SlotIdReading SimulateIdReading(const std::string& painted_id, const IdSensorConfig& config,
                                Random& rng, IdReadingOutcome* outcome) {
  SlotIdReading reading;
  const double u = rng.Uniform();
  IdReadingOutcome drawn = IdReadingOutcome::kCorrect;
  if (u < config.confusion_rate) {
    drawn = IdReadingOutcome::kConfused;
  } else if (u < config.confusion_rate + config.partial_rate) {
    drawn = IdReadingOutcome::kPartial;
  } else if (u < config.confusion_rate + config.partial_rate + config.unreadable_rate) {
    drawn = IdReadingOutcome::kUnreadable;
  }
  if (outcome != nullptr) *outcome = drawn;
  if (drawn == IdReadingOutcome::kUnreadable || painted_id.empty()) return reading;

  const size_t special = rng.Index(painted_id.size());
  for (size_t i = 0; i < painted_id.size(); ++i) {
    if (i == special && drawn == IdReadingOutcome::kConfused) {
      reading.digits.push_back(ConfusedDigit(painted_id[i], config, rng));
    } else if (i == special && drawn == IdReadingOutcome::kPartial) {
      reading.digits.push_back(DigitReading{});
    } else {
      reading.digits.push_back(CorrectDigit(painted_id[i], rng));
    }
  }
  return reading;
}

OdometrySensorModel::OdometrySensorModel(const OdometrySensorConfig& config,
                                         const VehicleParameters& vehicle, std::uint64_t seed,
                                         CompassField compass, bool has_compass)
    : config_(config),
      vehicle_(vehicle),
      wheel_rng_(Random::Derive(seed, kWheelStreamTag)),
      steering_rng_(Random::Derive(seed, kSteeringStreamTag)),
      imu_rng_(Random::Derive(seed, kImuStreamTag)),
      compass_(std::move(compass)),
      has_compass_(has_compass) {
  wheel_speed_scale_ = 1.0 + wheel_rng_.Gaussian(config_.wheel_speed_scale_sigma);
  gyro_bias_radps_ = imu_rng_.Gaussian(config_.gyro_bias_sigma_radps);
  heading_bias_rad_ = imu_rng_.Gaussian(config_.heading_bias_sigma_rad);
}

WheelSpeed OdometrySensorModel::MeasureWheel(const VehicleState& true_state, TimeNs t_ns) {
  return {t_ns, wheel_speed_scale_ * true_state.speed_mps +
                    wheel_rng_.Gaussian(config_.wheel_speed_sigma_mps)};
}

SteeringAngle OdometrySensorModel::MeasureSteering(const VehicleState& true_state, TimeNs t_ns) {
  return {t_ns, vehicle_.steering_ratio * true_state.road_wheel_angle_rad +
                    steering_rng_.Gaussian(config_.steering_wheel_sigma_rad)};
}

ImuSample OdometrySensorModel::MeasureImu(const VehicleState& true_state, TimeNs t_ns,
                                          double dt_s) {
  // The gyro noise is drawn before the heading noise, and the heading noise
  // is drawn with or without a compass, so that the streams stay aligned.
  ImuSample sample;
  sample.t_ns = t_ns;
  sample.yaw_rate_radps =
      true_state.yaw_rate_radps + gyro_bias_radps_ + imu_rng_.Gaussian(config_.gyro_sigma_radps);
  const double heading_noise_rad = imu_rng_.Gaussian(config_.heading_sigma_rad);
  if (has_compass_) {
    sample.heading_rad =
        NormalizeAngle(true_state.T_map_vehicle.yaw() + heading_bias_rad_ + heading_noise_rad +
                       compass_.DisturbanceAt(true_state.T_map_vehicle.translation()));
  }
  const double sqrt_dt = std::sqrt(dt_s);
  gyro_bias_radps_ += imu_rng_.Gaussian(config_.gyro_bias_walk_radps_per_sqrt_s * sqrt_dt);
  heading_bias_rad_ += imu_rng_.Gaussian(config_.heading_bias_walk_rad_per_sqrt_s * sqrt_dt);
  return sample;
}

OdometrySensorModel MakeOdometrySensorModel(const SensorConfig& sensors,
                                            const VehicleParameters& vehicle, const World& world,
                                            std::uint64_t seed) {
  return OdometrySensorModel(sensors.odometry, vehicle, seed,
                             CompassField(world, sensors.compass, seed),
                             sensors.compass.model != "none");
}

void SimulateOdometrySensors(const std::vector<VehicleState>& states,
                             const OdometrySensorConfig& config, const VehicleParameters& vehicle,
                             std::uint64_t seed, SensorLog* log) {
  SimulateOdometrySensors(states, OdometrySensorModel(config, vehicle, seed), log);
}

void SimulateOdometrySensors(const std::vector<VehicleState>& states, OdometrySensorModel model,
                             SensorLog* log) {
  const OdometrySensorConfig& config = model.config();
  for (TimeNs t : SampleTimes(states, config.wheel_rate_hz)) {
    log->wheel_speeds.push_back(model.MeasureWheel(StateAt(states, t), t));
  }
  for (TimeNs t : SampleTimes(states, config.steering_rate_hz)) {
    log->steering_angles.push_back(model.MeasureSteering(StateAt(states, t), t));
  }
  const double imu_period_s = 1.0 / config.imu_rate_hz;
  for (TimeNs t : SampleTimes(states, config.imu_rate_hz)) {
    log->imu_samples.push_back(model.MeasureImu(StateAt(states, t), t, imu_period_s));
  }
}

SlotObservationFrame SimulateSlotFrame(const World& world, const SE2& T_map_vehicle, TimeNs t_ns,
                                       const SensorConfig& config, Random& rng,
                                       std::vector<int>* labels) {
  const SlotSensorConfig& sc = config.slots;
  const TopView view{{sc.view_center_x_m, 0.0}, sc.view_length_m / 2, sc.view_width_m / 2};
  const SE2 T_vehicle_map = T_map_vehicle.inverse();
  const double reach_m =
      std::hypot(view.half_length_m, view.half_width_m) + std::abs(sc.view_center_x_m) + 1.0;
  SlotObservationFrame frame;
  frame.t_ns = t_ns;
  labels->clear();
  for (size_t i = 0; i < world.slots.size(); ++i) {
    const WorldSlot& slot = world.slots[i];
    if ((slot.corners_map[0] - T_map_vehicle.translation()).norm() > reach_m) continue;
    std::array<Eigen::Vector2d, 4> corners_vehicle;
    for (int k = 0; k < 4; ++k) corners_vehicle[k] = T_vehicle_map * slot.corners_map[k];
    if (!view.Contains(corners_vehicle[0]) || !view.Contains(corners_vehicle[1])) continue;
    if (rng.Bernoulli(sc.miss_rate)) continue;
    SlotObservation obs = ObserveSlot(corners_vehicle, view, sc, rng);
    obs.detection_confidence = rng.Uniform(0.7, 1.0);
    if (!slot.painted_id.empty() && slot.id_legible) {
      obs.id = SimulateIdReading(slot.painted_id, config.ids, rng);
    }
    frame.slots.push_back(obs);
    labels->push_back(static_cast<int>(i));
  }
  const int false_count = rng.Poisson(sc.false_per_frame);
  for (int k = 0; k < false_count; ++k) {
    frame.slots.push_back(FalseSlot(view, config, rng));
    labels->push_back(-1);
  }
  return frame;
}

TagObservationFrame SimulateTagFrame(const World& world, const SE2& T_map_vehicle, TimeNs t_ns,
                                     const TagSensorConfig& config, Random& rng) {
  const SE2 T_vehicle_camera(config.camera_x_m, config.camera_y_m, DegToRad(config.camera_yaw_deg));
  const SE2 T_map_camera = T_map_vehicle * T_vehicle_camera;
  const SE2 T_camera_map = T_map_camera.inverse();
  const double half_fov = DegToRad(config.horizontal_fov_deg) / 2;
  const double max_incidence = DegToRad(config.max_incidence_deg);
  TagObservationFrame frame;
  frame.t_ns = t_ns;
  for (const WorldTag& tag : world.tags) {
    const Eigen::Vector2d p_camera = T_camera_map * tag.p_map;
    const double range = p_camera.norm();
    if (range < config.min_range_m || range >= config.max_range_m) continue;
    const double bearing = std::atan2(p_camera.y(), p_camera.x());
    if (std::abs(bearing) > half_fov) continue;
    const Eigen::Vector2d to_camera = T_map_camera.translation() - tag.p_map;
    const Eigen::Vector2d normal(std::cos(tag.normal_yaw_rad), std::sin(tag.normal_yaw_rad));
    if (normal.dot(to_camera) <= range * std::cos(max_incidence)) continue;
    // Stop 2 cm short of the tag so its own mount does not block it.
    const Eigen::Vector2d near_tag = tag.p_map + 0.02 * to_camera / range;
    if (SegmentBlocked(world, T_map_camera.translation(), near_tag,
                       tag.on_pillar ? -1 : tag.mount_index,
                       tag.on_pillar ? tag.mount_index : -1)) {
      continue;
    }
    const double r = range / config.max_range_m;
    if (rng.Bernoulli(config.miss_rate +
                      (config.miss_rate_at_max_range - config.miss_rate) * r * r)) {
      continue;
    }
    const double range_sigma = config.range_sigma_m + config.range_sigma_per_m * range;
    const double bearing_sigma = config.bearing_sigma_rad + config.bearing_sigma_per_m * range;
    const double yaw_sigma = config.yaw_sigma_rad + config.yaw_sigma_per_m * range;
    TagObservation obs;
    obs.tag_id = tag.tag_id;
    obs.range_m = range + rng.Gaussian(range_sigma);
    obs.bearing_rad = bearing + rng.Gaussian(bearing_sigma);
    const Eigen::Vector2d measured_camera =
        obs.range_m * Eigen::Vector2d(std::cos(obs.bearing_rad), std::sin(obs.bearing_rad));
    obs.p_vehicle = T_vehicle_camera * measured_camera;
    obs.yaw_vehicle_rad =
        NormalizeAngle(tag.normal_yaw_rad - T_map_vehicle.yaw() + rng.Gaussian(yaw_sigma));
    obs.yaw_sigma_rad = yaw_sigma;
    // Covariance of the point from range and bearing noise, in the vehicle
    // frame: J diag(sr^2, sb^2) J^T with J = d(r cos b, r sin b)/d(r, b).
    Eigen::Matrix2d jacobian;
    jacobian << std::cos(obs.bearing_rad), -obs.range_m * std::sin(obs.bearing_rad),
        std::sin(obs.bearing_rad), obs.range_m * std::cos(obs.bearing_rad);
    const Eigen::Matrix2d cov_camera =
        jacobian *
        Eigen::Vector2d(range_sigma * range_sigma, bearing_sigma * bearing_sigma).asDiagonal() *
        jacobian.transpose();
    const Eigen::Matrix2d R = T_vehicle_camera.rotation();
    obs.covariance_vehicle = R * cov_camera * R.transpose();
    frame.tags.push_back(obs);
  }
  return frame;
}

}  // namespace parkslam::sim
