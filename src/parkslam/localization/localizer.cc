#include "parkslam/localization/localizer.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "parkslam/common/alignment.h"
#include "parkslam/common/angles.h"
#include "parkslam/common/chi_square.h"
#include "parkslam/common/field_checker.h"

namespace parkslam::localization {
namespace {

double Square(double x) { return x * x; }

// d(R(yaw)^T v)/d(yaw) for R(yaw)^T = [c s; -s c].
Eigen::Vector2d DRotTransposeDYaw(double yaw, const Eigen::Vector2d& v) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {-s * v.x() + c * v.y(), -c * v.x() - s * v.y()};
}

// The best full ID of a reading when it is confident enough, else "".
std::string ConfidentId(const SlotIdReading& id, double min_confidence) {
  if (id.empty() || id.partial() || id.confidence() < min_confidence) return "";
  return id.best();
}

}  // namespace

const char* ToString(LocalizerState state) {
  switch (state) {
    case LocalizerState::kUninitialized:
      return "uninitialized";
    case LocalizerState::kTracking:
      return "tracking";
    case LocalizerState::kLost:
      return "lost";
  }
  return "uninitialized";
}

LandmarkUse& LandmarkUse::operator+=(const LandmarkUse& other) {
  observed += other.observed;
  associated += other.associated;
  used += other.used;
  rejected_no_map_landmark += other.rejected_no_map_landmark;
  rejected_gate += other.rejected_gate;
  while_lost += other.while_lost;
  return *this;
}

bool LocalizerOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.Positive(corner_sigma_floor_m, "corner_sigma_floor_m");
  c.NonNegative(map_yaw_sigma_rad, "map_yaw_sigma_rad");
  c.NonNegative(wheel_scale_walk_per_sqrt_m, "wheel_scale_walk_per_sqrt_m");
  c.NonNegative(map_corner_sigma_floor_m, "map_corner_sigma_floor_m");
  c.NonNegative(tag_map_sigma_m, "tag_map_sigma_m");
  c.NonNegative(tag_map_yaw_sigma_rad, "tag_map_yaw_sigma_rad");
  c.Rate(id_min_confidence, "id_min_confidence");
  c.Positive(nn_radius_m, "nn_radius_m");
  c.Between(gate_probability, 0.5, 1.0, "gate_probability", "");
  c.Positive(lost_after_s, "lost_after_s");
  c.AtLeast(lost_min_rejected, 1, "lost_min_rejected");
  c.Positive(lost_position_sigma_m, "lost_position_sigma_m");
  c.Positive(reloc_window_s, "reloc_window_s");
  c.Positive(reloc_inlier_m, "reloc_inlier_m");
  c.AtLeast(reloc_min_inliers, 2, "reloc_min_inliers");
  c.AtLeast(reloc_min_landmarks, 1, "reloc_min_landmarks");
  c.PositiveAtMost(reloc_ambiguity_ratio, 1.0, "reloc_ambiguity_ratio", "");
  c.Positive(reloc_position_sigma_m, "reloc_position_sigma_m");
  c.Positive(reloc_yaw_sigma_rad, "reloc_yaw_sigma_rad");
  c.Positive(entrance_position_sigma_m, "entrance_position_sigma_m");
  c.Positive(entrance_yaw_sigma_rad, "entrance_yaw_sigma_rad");
  return c.ok();
}

Localizer::Localizer(const SemanticMap& map, const LocalizerOptions& options,
                     const odometry::OdometryEkfOptions& odometry_options)
    : map_(map),
      options_(options),
      odometry_(std::make_unique<odometry::OdometryEkf>(odometry_options)) {
  // Without the scale's estimate its variance stays 0: no update moves it.
  P_(kScale, kScale) =
      options_.estimate_wheel_scale ? Square(odometry_options.wheel_scale_sigma) : 0.0;
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument("localizer options: " + error);
  if (!odometry_options.IsValid(&error)) throw std::invalid_argument("odometry options: " + error);
  for (int i = 0; i < static_cast<int>(map_.slots.size()); ++i) {
    if (!map_.slots[i].temporary && !map_.slots[i].id.empty()) slot_by_id_[map_.slots[i].id] = i;
  }
  for (int i = 0; i < static_cast<int>(map_.tags.size()); ++i) {
    tag_by_id_[map_.tags[i].tag_id] = i;
  }
  for (int dof = 1; dof <= 4; ++dof) {
    gate_chi2_[dof] = ChiSquareQuantile(options_.gate_probability, dof);
  }
}

Localizer::~Localizer() = default;
Localizer::Localizer(Localizer&&) noexcept = default;
Localizer& Localizer::operator=(Localizer&&) noexcept = default;

void Localizer::SetPose(const SE2& T_map_vehicle, const Eigen::Matrix3d& covariance) {
  // The pose is new; what the drive has taught of the odometry's scale stays.
  x_.head<3>() << T_map_vehicle.x(), T_map_vehicle.y(), T_map_vehicle.yaw();
  P_.topLeftCorner<3, 3>() = covariance;
  P_.block<3, 1>(0, kScale).setZero();
  P_.block<1, 3>(kScale, 0).setZero();
  state_ = LocalizerState::kTracking;
  recent_outcomes_.clear();
  map_position_var_ = 0.0;
}

std::optional<std::pair<SE2, Eigen::Matrix3d>> Localizer::TrackedAt(TimeNs t_ns) const {
  if (state_ != LocalizerState::kTracking || last_frame_ns_ != t_ns) return std::nullopt;
  return std::make_pair(pose(), covariance());
}

SE2 Localizer::PredictedPose() const {
  if (!odometry_->initialized()) return pose();
  const SE2 motion = odometry_->MotionSinceClone().T_clone_now;
  return pose() * SE2(DistanceFactor() * motion.translation(), motion.yaw());
}

double Localizer::DistanceFactor() const {
  if (!options_.estimate_wheel_scale) return 1.0;
  return 1.0 - (x_[kScale] - odometry_->state()[odometry::OdometryEkf::kWheelScale]);
}

void Localizer::Predict(const odometry::OdometryEkf::RelativeMotion& motion) {
  // x' = x (+) delta, the odometry's distance corrected for the wheel
  // speed's scale error s: the odometry moved by d with its own estimate
  // s_o of that error (which it learns in turns, from the steering and the
  // gyro), so the car moved (1 + s_o) / (1 + s) d ~ (1 - (s - s_o)) d:
  //   t' = t + (1 - (s - s_o)) R(yaw) d,  yaw' = yaw + phi,
  //   s' = s + w,  var(w) = walk^2 |d|.
  // The motion's own covariance (the dead reckoning's, since the last
  // frame) enters through J_d.
  const Eigen::Matrix2d R = pose().rotation();
  const Eigen::Vector2d Rd = R * motion.T_clone_now.translation();
  const double scale = DistanceFactor();
  // d(R d)/d(yaw) = (-(R d)_y, (R d)_x).
  StateCovariance J_x = StateCovariance::Identity();
  J_x.block<2, 1>(0, 2) = scale * Eigen::Vector2d(-Rd.y(), Rd.x());
  J_x.block<2, 1>(0, kScale) = -Rd;
  Eigen::Matrix<double, 4, 3> J_d = Eigen::Matrix<double, 4, 3>::Zero();
  J_d.topLeftCorner<2, 2>() = scale * R;
  J_d(2, 2) = 1.0;
  x_.head<2>() += scale * Rd;
  x_[2] = NormalizeAngle(x_[2] + motion.T_clone_now.yaw());
  P_ = J_x * P_ * J_x.transpose() + J_d * motion.covariance * J_d.transpose();
  if (options_.estimate_wheel_scale) {
    P_(kScale, kScale) += Square(options_.wheel_scale_walk_per_sqrt_m) * Rd.norm();
  }
}

template <int N>
bool Localizer::Update(const Eigen::Matrix<double, N, 1>& innovation,
                       const Eigen::Matrix<double, N, 3>& H_pose,
                       const Eigen::Matrix<double, N, N>& R) {
  // Landmarks see the pose only; the scale error follows through P's
  // cross-covariance (what the pose has moved since, it has moved too far).
  Eigen::Matrix<double, N, 4> H = Eigen::Matrix<double, N, 4>::Zero();
  H.template leftCols<3>() = H_pose;
  const Eigen::Matrix<double, N, N> S = H * P_ * H.transpose() + R;
  const Eigen::LLT<Eigen::Matrix<double, N, N>> llt(S);
  if (llt.info() != Eigen::Success) return false;
  const double chi2 = innovation.dot(llt.solve(innovation));
  if (!(chi2 < gate_chi2_[N])) return false;
  const Eigen::Matrix<double, 4, N> K =
      P_ * H.transpose() * llt.solve(Eigen::Matrix<double, N, N>::Identity());
  x_ += K * innovation;
  x_[2] = NormalizeAngle(x_[2]);
  const StateCovariance I_KH = StateCovariance::Identity() - K * H;
  P_ = I_KH * P_ * I_KH.transpose() + K * R * K.transpose();
  return true;
}

std::optional<double> Localizer::UpdateSlot(const SlotObservation& obs, LandmarkUse* use) {
  ++use->observed;
  // The two entrance corners (the corners a detector really sees), matched
  // to two corners of a map slot: its entrance (0, 1), or, where no entrance
  // is near, one of its side lines (1, 2 or 3, 0) or its back line (2, 3).
  // A side line: the detector took the side of a slot seen end-on for the
  // entrance of another (a row's first slot from the cross aisle: its side
  // line runs between two L corners and looks like a parallel slot's
  // entrance). The back line: a row seen from the lane behind it, where the
  // dividers meet the back line in T corners as they meet the entrance line
  // on the aisle side. Either way the same painted corners are seen, and the
  // pose is measured against them as well.
  const double obs_sigma = std::max(obs.corner_sigma_m, options_.corner_sigma_floor_m);
  const SE2 pose = this->pose();
  const SE2 T_vehicle_map = pose.inverse();
  Eigen::Vector4d z;
  z << obs.corners_vehicle[0], obs.corners_vehicle[1];
  struct Pairing {
    int slot = 0;
    int a = 0, b = 1;  // the map slot's corners that obs's corners 0 and 1 are
  };
  auto innovation_for = [&](const Pairing& p) {
    const MapSlot& slot = map_.slots[p.slot];
    Eigen::Vector4d h;
    h << T_vehicle_map * slot.corners_map[p.a], T_vehicle_map * slot.corners_map[p.b];
    return Eigen::Vector4d(z - h);
  };
  auto map_variance = [&](const Pairing& p, int corner) {
    return Square(
        std::max(map_.slots[p.slot].corner_sigma_m[corner], options_.map_corner_sigma_floor_m));
  };
  auto model_for = [&](const Pairing& p, Eigen::Matrix<double, 4, 3>* H, Eigen::Matrix4d* R) {
    H->setZero();
    R->setZero();
    const Eigen::Matrix2d Rt = pose.rotation().transpose();
    const int corners[2] = {p.a, p.b};
    for (int j = 0; j < 2; ++j) {
      H->block<2, 2>(2 * j, 0) = -Rt;
      H->block<2, 1>(2 * j, 2) = DRotTransposeDYaw(
          pose.yaw(), map_.slots[p.slot].corners_map[corners[j]] - pose.translation());
      R->block<2, 2>(2 * j, 2 * j) =
          Eigen::Matrix2d::Identity() * (Square(obs_sigma) + map_variance(p, corners[j]));
    }
  };
  // How far the pairing's corners are from the observed ones (the larger).
  auto distance = [&](const Pairing& p) {
    const Eigen::Vector4d y = innovation_for(p);
    return std::max(y.head<2>().norm(), y.tail<2>().norm());
  };
  auto nearest_first = [&](std::vector<Pairing> pairings) {
    std::vector<std::pair<double, Pairing>> near;
    for (const Pairing& p : pairings) {
      const double d = distance(p);
      if (d <= options_.nn_radius_m) near.push_back({d, p});
    }
    std::stable_sort(near.begin(), near.end(),
                     [](const auto& x, const auto& y) { return x.first < y.first; });
    std::vector<Pairing> sorted;
    for (const auto& [d, p] : near) sorted.push_back(p);
    return sorted;
  };

  std::vector<Pairing> candidates;
  const std::string id = ConfidentId(obs.id, options_.id_min_confidence);
  const auto by_id = id.empty() ? slot_by_id_.end() : slot_by_id_.find(id);
  if (by_id != slot_by_id_.end()) candidates.push_back({by_id->second, 0, 1});
  // Nearest neighbours, best first (also the fall-back for a misread ID).
  std::vector<Pairing> entrances;
  for (int i = 0; i < static_cast<int>(map_.slots.size()); ++i) {
    if (by_id == slot_by_id_.end() || i != by_id->second) entrances.push_back({i, 0, 1});
  }
  for (const Pairing& p : nearest_first(std::move(entrances))) candidates.push_back(p);
  if (candidates.empty()) {
    // A side line with at least one corner the map saw (a side of two
    // guessed corners would let a wrong pose pass a gate of 0.4 m sigmas);
    // the back line only where the map saw both of its corners (one seen
    // and one guessed would hold the pose to a guess across the slot's
    // width, where a side line's guessed corner lies along the car's way).
    std::vector<Pairing> sides;
    for (int i = 0; i < static_cast<int>(map_.slots.size()); ++i) {
      const MapSlot& slot = map_.slots[i];
      for (const auto& [a, b] : {std::pair{1, 2}, std::pair{3, 0}}) {
        if (slot.corner_observed[a] || slot.corner_observed[b]) sides.push_back({i, a, b});
      }
      if (slot.corner_observed[2] && slot.corner_observed[3]) sides.push_back({i, 2, 3});
    }
    candidates = nearest_first(std::move(sides));
  }
  if (candidates.empty()) {
    ++use->rejected_no_map_landmark;
    return std::nullopt;
  }
  ++use->associated;
  for (const Pairing& p : candidates) {
    Eigen::Matrix<double, 4, 3> H;
    Eigen::Matrix4d R;
    model_for(p, &H, &R);
    if (Update<4>(innovation_for(p), H, R)) {
      ++use->used;
      // A side line anchors the pose on its better-known corner (the other
      // may be guessed), an entrance or a back line on both.
      const double var_a = map_variance(p, p.a), var_b = map_variance(p, p.b);
      const bool side_line = p.a == 1 || p.a == 3;
      return side_line ? std::min(var_a, var_b) : (var_a + var_b) / 2;
    }
  }
  ++use->rejected_gate;
  return std::nullopt;
}

std::optional<double> Localizer::UpdateTag(const TagObservation& obs, LandmarkUse* use) {
  ++use->observed;
  const auto it = tag_by_id_.find(obs.tag_id);
  if (it == tag_by_id_.end()) {
    ++use->rejected_no_map_landmark;
    return std::nullopt;
  }
  ++use->associated;
  const MapTag& tag = map_.tags[it->second];
  const SE2 pose = this->pose();
  const Eigen::Matrix2d Rt = pose.rotation().transpose();
  Eigen::Vector3d y;
  y.head<2>() = obs.p_vehicle - Rt * (tag.p_map - pose.translation());
  y[2] = AngleDiff(obs.yaw_vehicle_rad, tag.yaw_map_rad - pose.yaw());
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  H.topLeftCorner<2, 2>() = -Rt;
  H.block<2, 1>(0, 2) = DRotTransposeDYaw(pose.yaw(), tag.p_map - pose.translation());
  H(2, 2) = -1.0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
  R.topLeftCorner<2, 2>() =
      obs.covariance_vehicle + Eigen::Matrix2d::Identity() * Square(options_.tag_map_sigma_m);
  R(2, 2) = Square(obs.yaw_sigma_rad) + Square(options_.tag_map_yaw_sigma_rad);
  if (!Update<3>(y, H, R)) {
    ++use->rejected_gate;
    return std::nullopt;
  }
  ++use->used;
  return Square(options_.tag_map_sigma_m);
}

Localizer::Support Localizer::CountInliers(const SE2& T_map_now) const {
  const SE2 T_odom_now = buffer_.back().T_odom_vehicle;
  std::set<int> matched;
  Support support;
  auto add = [&](const SE2& T_now_frame, const Eigen::Vector2d& p_frame,
                 const Eigen::Vector2d& p_map) {
    ++support.inliers;
    support.points_now.push_back(T_now_frame * p_frame);
    support.points_map.push_back(p_map);
  };
  for (const BufferedFrame& frame : buffer_) {
    const SE2 T_now_frame = T_odom_now.inverse() * frame.T_odom_vehicle;
    const SE2 T_map_frame = T_map_now * T_now_frame;
    for (const SlotObservation& obs : frame.slots) {
      const std::string id = ConfidentId(obs.id, options_.id_min_confidence);
      const auto by_id = id.empty() ? slot_by_id_.end() : slot_by_id_.find(id);
      const Eigen::Vector2d c0 = T_map_frame * obs.corners_vehicle[0];
      const Eigen::Vector2d c1 = T_map_frame * obs.corners_vehicle[1];
      // On a slot's entrance, or on its back line where the map saw both
      // of its corners (a row seen from the lane behind it, as UpdateSlot).
      bool hit = false;
      for (int i = 0; i < static_cast<int>(map_.slots.size()) && !hit; ++i) {
        const MapSlot& slot = map_.slots[i];
        for (const auto& [a, b] : {std::pair{0, 1}, std::pair{2, 3}}) {
          if (a == 2 && !(slot.corner_observed[2] && slot.corner_observed[3])) continue;
          if ((slot.corners_map[a] - c0).norm() < options_.reloc_inlier_m &&
              (slot.corners_map[b] - c1).norm() < options_.reloc_inlier_m) {
            hit = true;
            // An entrance whose confident reading names another map slot
            // speaks against the hypothesis (a row's slots repeat every
            // width: one slot off, the geometry alone fits as well).
            if (a == 0 && by_id != slot_by_id_.end() && by_id->second != i) {
              ++support.conflicts;
              break;
            }
            add(T_now_frame, obs.corners_vehicle[0], slot.corners_map[a]);
            add(T_now_frame, obs.corners_vehicle[1], slot.corners_map[b]);
            --support.inliers;  // one observation, two points
            matched.insert(i);
            break;
          }
        }
      }
    }
    for (const TagObservation& obs : frame.tags) {
      const auto it = tag_by_id_.find(obs.tag_id);
      if (it == tag_by_id_.end()) continue;
      const Eigen::Vector2d p_map = map_.tags[it->second].p_map;
      if ((p_map - T_map_frame * obs.p_vehicle).norm() < options_.reloc_inlier_m) {
        add(T_now_frame, obs.p_vehicle, p_map);
        matched.insert(-1 - it->second);
      }
    }
  }
  support.landmarks.assign(matched.begin(), matched.end());
  return support;
}

bool Localizer::TryRelocalize(TimeNs t_ns) {
  if (buffer_.empty() || buffer_.back().t_ns != t_ns) return false;
  const BufferedFrame& now = buffer_.back();
  // Hypotheses from this frame's confident IDs and tags.
  std::vector<SE2> hypotheses;
  for (const SlotObservation& obs : now.slots) {
    const std::string id = ConfidentId(obs.id, options_.id_min_confidence);
    const auto it = id.empty() ? slot_by_id_.end() : slot_by_id_.find(id);
    if (it == slot_by_id_.end()) continue;
    const MapSlot& slot = map_.slots[it->second];
    hypotheses.push_back(AlignPointSets({obs.corners_vehicle[0], obs.corners_vehicle[1]},
                                        {slot.corners_map[0], slot.corners_map[1]}));
  }
  for (const TagObservation& obs : now.tags) {
    const auto it = tag_by_id_.find(obs.tag_id);
    if (it == tag_by_id_.end()) continue;
    const MapTag& tag = map_.tags[it->second];
    const SE2 T_map_tag(tag.p_map, tag.yaw_map_rad);
    const SE2 T_vehicle_tag(obs.p_vehicle, obs.yaw_vehicle_rad);
    hypotheses.push_back(T_map_tag * T_vehicle_tag.inverse());
  }
  // Each hypothesis scored by its inliers less the readings that contradict
  // it; the best must stand clear of every rival elsewhere (over 1 m away).
  std::vector<Support> supports;
  int best = -1;
  for (int h = 0; h < static_cast<int>(hypotheses.size()); ++h) {
    supports.push_back(CountInliers(hypotheses[h]));
    if (best < 0 || supports[h].score() > supports[best].score()) best = h;
  }
  if (best < 0) return false;
  int rival_score = 0;
  for (int h = 0; h < static_cast<int>(hypotheses.size()); ++h) {
    if ((hypotheses[best].translation() - hypotheses[h].translation()).norm() > 1.0) {
      rival_score = std::max(rival_score, supports[h].score());
    }
  }
  const Support& best_support = supports[best];
  if (best_support.score() < options_.reloc_min_inliers ||
      static_cast<int>(best_support.landmarks.size()) < options_.reloc_min_landmarks ||
      rival_score > options_.reloc_ambiguity_ratio * best_support.score()) {
    return false;
  }
  Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
  P.diagonal() << Square(options_.reloc_position_sigma_m), Square(options_.reloc_position_sigma_m),
      Square(options_.reloc_yaw_sigma_rad);
  // Refined on every supporting point of the last seconds.
  SetPose(AlignPointSets(best_support.points_now, best_support.points_map), P);
  return true;
}

std::optional<LocalizationEstimate> Localizer::Process(const SensorEvent& event) {
  const TimeNs t_ns = EventTime(event);
  if (!odometry_->initialized()) {
    // The odometry frame only serves relative motion: any start will do.
    odometry_->Initialize(t_ns, SE2(), 0.01);
  }
  if (!odometry_->Process(event)) return std::nullopt;
  const auto* slot_frame = std::get_if<SlotObservationFrame>(&event);
  const auto* tag_frame = std::get_if<TagObservationFrame>(&event);
  if (slot_frame == nullptr && tag_frame == nullptr) return std::nullopt;

  const odometry::OdometryEkf::RelativeMotion motion = odometry_->MotionSinceClone();
  odometry_->ClonePose();
  if (state_ != LocalizerState::kUninitialized) Predict(motion);
  last_frame_ns_ = t_ns;

  BufferedFrame frame;
  frame.t_ns = t_ns;
  frame.T_odom_vehicle = odometry_->pose();
  if (slot_frame != nullptr) frame.slots = slot_frame->slots;
  if (tag_frame != nullptr) frame.tags = tag_frame->tags;
  buffer_.push_back(frame);
  while (!buffer_.empty() && ToSeconds(t_ns - buffer_.front().t_ns) > options_.reloc_window_s) {
    buffer_.pop_front();
  }

  LocalizationEstimate estimate;
  estimate.t_ns = t_ns;
  if (state_ == LocalizerState::kTracking) {
    double map_var_sum = 0.0;
    int map_var_count = 0;
    auto anchored = [&](std::optional<double> map_var) {
      if (!map_var) return;
      map_var_sum += *map_var;
      ++map_var_count;
    };
    for (const SlotObservation& obs : frame.slots) anchored(UpdateSlot(obs, &estimate.slots));
    for (const TagObservation& obs : frame.tags) anchored(UpdateTag(obs, &estimate.tags));
    if (map_var_count > 0) map_position_var_ = map_var_sum / map_var_count;
    for (int i = 0; i < estimate.used(); ++i) recent_outcomes_.push_back({t_ns, true});
    for (int i = 0; i < estimate.rejected(); ++i) recent_outcomes_.push_back({t_ns, false});
    while (!recent_outcomes_.empty() &&
           ToSeconds(t_ns - recent_outcomes_.front().first) > options_.lost_after_s) {
      recent_outcomes_.pop_front();
    }
    const bool any_accepted = std::any_of(recent_outcomes_.begin(), recent_outcomes_.end(),
                                          [](const auto& o) { return o.second; });
    const double position_sigma = std::sqrt(std::max(P_(0, 0), P_(1, 1)));
    if ((!any_accepted &&
         static_cast<int>(recent_outcomes_.size()) >= options_.lost_min_rejected) ||
        position_sigma > options_.lost_position_sigma_m) {
      state_ = LocalizerState::kLost;
      recent_outcomes_.clear();
    }
  } else {
    estimate.slots.observed = estimate.slots.while_lost = static_cast<int>(frame.slots.size());
    estimate.tags.observed = estimate.tags.while_lost = static_cast<int>(frame.tags.size());
    estimate.relocalized = TryRelocalize(t_ns);
  }
  estimate.T_map_vehicle = pose();
  estimate.covariance = covariance();
  if (map_position_var_ > 0.0) {
    estimate.covariance.diagonal() +=
        Eigen::Vector3d(map_position_var_, map_position_var_, Square(options_.map_yaw_sigma_rad));
  }
  estimate.state = state_;
  return estimate;
}

}  // namespace parkslam::localization
