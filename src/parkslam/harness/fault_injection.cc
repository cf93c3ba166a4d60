#include "parkslam/harness/fault_injection.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <utility>

#include "parkslam/common/angles.h"

namespace parkslam::harness {
namespace {

struct KindName {
  FaultKind kind;
  const char* name;
};
constexpr KindName kKindNames[] = {
    {FaultKind::kCameraGap, "camera-gap"},       {FaultKind::kCameraBlack, "camera-black"},
    {FaultKind::kCameraFrozen, "camera-frozen"}, {FaultKind::kLateFrames, "late-frames"},
    {FaultKind::kImuSpikes, "imu-spikes"},       {FaultKind::kHeadingJump, "heading-jump"},
    {FaultKind::kWheelDropout, "wheel-dropout"}, {FaultKind::kClockJitter, "clock-jitter"},
};

// Spikes of imu-spikes come this far apart.
constexpr TimeNs kSpikeInterval_ns = 500'000'000;

bool IsFrame(const SensorEvent& event) {
  return std::holds_alternative<CameraFrame>(event) ||
         std::holds_alternative<SlotObservationFrame>(event) ||
         std::holds_alternative<TagObservationFrame>(event);
}

double ParseNumber(const std::string& text, const std::string& what, const std::string& spec) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || !std::isfinite(value)) {
    throw std::invalid_argument("fault '" + spec + "': " + what + ": not a number: '" + text + "'");
  }
  return value;
}

}  // namespace

const char* ToString(FaultKind kind) {
  for (const KindName& k : kKindNames) {
    if (k.kind == kind) return k.name;
  }
  return "?";
}

double DefaultMagnitude(FaultKind kind) {
  switch (kind) {
    case FaultKind::kLateFrames:
      return 0.5;
    case FaultKind::kImuSpikes:
      return 2.0;
    case FaultKind::kHeadingJump:
      return 0.5;
    case FaultKind::kClockJitter:
      return 0.02;
    default:
      return 0.0;
  }
}

std::string SensorFault::ToText() const {
  std::string text = std::string(ToString(kind)) + "@" + std::to_string(start_s) + "+" +
                     std::to_string(duration_s);
  if (kind == FaultKind::kCameraBlack || kind == FaultKind::kCameraFrozen) {
    text += ",camera=" + camera;
  }
  if (magnitude != 0.0) text += ",magnitude=" + std::to_string(magnitude);
  return text;
}

SensorFault ParseSensorFault(const std::string& text) {
  const std::size_t at = text.find('@');
  if (at == std::string::npos) {
    throw std::invalid_argument("fault '" + text + "': expected KIND@START+DURATION");
  }
  const std::string kind = text.substr(0, at);
  SensorFault fault;
  bool known = false;
  for (const KindName& k : kKindNames) {
    if (kind == k.name) {
      fault.kind = k.kind;
      known = true;
    }
  }
  if (!known) {
    std::string names;
    for (const KindName& k : kKindNames) names += std::string(names.empty() ? "" : ", ") + k.name;
    throw std::invalid_argument("fault '" + text + "': unknown kind '" + kind + "' (" + names +
                                ")");
  }
  std::string rest = text.substr(at + 1);
  std::vector<std::string> parts;
  for (std::size_t comma; (comma = rest.find(',')) != std::string::npos;) {
    parts.push_back(rest.substr(0, comma));
    rest = rest.substr(comma + 1);
  }
  parts.push_back(rest);
  const std::size_t plus = parts[0].find('+');
  if (plus == std::string::npos) {
    throw std::invalid_argument("fault '" + text + "': expected START+DURATION after '@'");
  }
  fault.start_s = ParseNumber(parts[0].substr(0, plus), "START", text);
  fault.duration_s = ParseNumber(parts[0].substr(plus + 1), "DURATION", text);
  if (fault.start_s < 0.0 || fault.duration_s <= 0.0 || fault.start_s + fault.duration_s > 1e6) {
    throw std::invalid_argument(
        "fault '" + text + "': START must be >= 0 and DURATION > 0 (seconds, under 1e6 in all)");
  }
  for (std::size_t k = 1; k < parts.size(); ++k) {
    const std::size_t eq = parts[k].find('=');
    const std::string key = parts[k].substr(0, eq);
    const std::string value = eq == std::string::npos ? "" : parts[k].substr(eq + 1);
    if (key == "camera" && !value.empty()) {
      fault.camera = value;
    } else if (key == "magnitude") {
      fault.magnitude = ParseNumber(value, "magnitude", text);
      if (fault.magnitude < 0.0 || fault.magnitude > 1e3) {
        throw std::invalid_argument("fault '" + text + "': magnitude must lie in [0, 1000]");
      }
    } else {
      throw std::invalid_argument("fault '" + text + "': unknown option '" + parts[k] +
                                  "' (camera=NAME, magnitude=X)");
    }
  }
  if (fault.magnitude == 0.0) fault.magnitude = DefaultMagnitude(fault.kind);
  return fault;
}

FaultInjectingSource::FaultInjectingSource(SensorSource& inner, std::vector<SensorFault> faults,
                                           std::uint64_t seed)
    : inner_(inner),
      faults_(std::move(faults)),
      rng_(seed),
      last_image_(faults_.size()),
      next_spike_ns_(faults_.size(), -1) {}

bool FaultInjectingSource::Active(const SensorFault& fault, TimeNs t_ns) const {
  const double t_s = ToSeconds(t_ns - start_ns_.value_or(t_ns));
  return t_s >= fault.start_s && t_s < fault.start_s + fault.duration_s;
}

bool FaultInjectingSource::Apply(SensorEvent* event) {
  const TimeNs t_ns = EventTime(*event);
  for (std::size_t i = 0; i < faults_.size(); ++i) {
    const SensorFault& fault = faults_[i];
    const bool active = Active(fault, t_ns);
    auto* frame = std::get_if<CameraFrame>(event);
    ImagePlane* image = nullptr;
    if (frame != nullptr) {
      for (std::size_t k = 0; k < frame->cameras.size() && k < frame->images.size(); ++k) {
        if (frame->cameras[k] == fault.camera) image = &frame->images[k];
      }
    }
    switch (fault.kind) {
      case FaultKind::kCameraGap:
        if (active && IsFrame(*event)) {
          ++injected_.frames_dropped;
          return false;
        }
        break;
      case FaultKind::kCameraBlack:
        if (active && image != nullptr && image->pixels != nullptr) {
          image->pixels = std::make_shared<const std::vector<std::uint8_t>>(
              static_cast<std::size_t>(image->width) * static_cast<std::size_t>(image->height), 0);
          ++injected_.images_blackened;
        }
        break;
      case FaultKind::kCameraFrozen:
        if (image == nullptr || image->pixels == nullptr) break;
        if (!active) {
          last_image_[i] = *image;
        } else if (last_image_[i].pixels != nullptr) {
          *image = last_image_[i];
          ++injected_.images_frozen;
        }
        break;
      case FaultKind::kImuSpikes:
        if (auto* imu = std::get_if<ImuSample>(event); imu != nullptr && active) {
          if (next_spike_ns_[i] < 0) next_spike_ns_[i] = t_ns;
          if (t_ns >= next_spike_ns_[i]) {
            const double sign = std::bernoulli_distribution(0.5)(rng_) ? 1.0 : -1.0;
            imu->yaw_rate_radps += sign * fault.magnitude;
            if (imu->heading_rad) {
              imu->heading_rad = NormalizeAngle(*imu->heading_rad - sign * 0.25 * fault.magnitude);
            }
            next_spike_ns_[i] += kSpikeInterval_ns;
            ++injected_.imu_spikes;
          }
        }
        break;
      case FaultKind::kHeadingJump:
        if (auto* imu = std::get_if<ImuSample>(event);
            imu != nullptr && imu->heading_rad && active) {
          imu->heading_rad = NormalizeAngle(*imu->heading_rad + fault.magnitude);
          ++injected_.heading_samples_shifted;
        }
        break;
      case FaultKind::kWheelDropout:
        if (active && std::holds_alternative<WheelSpeed>(*event)) {
          ++injected_.wheel_samples_dropped;
          return false;
        }
        break;
      case FaultKind::kClockJitter:
        if (active) {
          const TimeNs shift = static_cast<TimeNs>(
              std::llround(std::normal_distribution<double>(0.0, fault.magnitude)(rng_) * 1e9));
          std::visit([shift](auto& e) { e.t_ns = std::max<TimeNs>(0, e.t_ns + shift); }, *event);
          ++injected_.events_jittered;
        }
        break;
      case FaultKind::kLateFrames:
        break;  // in Pull()
    }
  }
  return true;
}

std::optional<SensorEvent> FaultInjectingSource::Pull() {
  while (auto event = inner_.Next()) {
    if (!start_ns_) start_ns_ = EventTime(*event);
    const TimeNs t_ns = EventTime(*event);
    if (!Apply(&*event)) continue;
    double delay_s = 0.0;
    for (const SensorFault& fault : faults_) {
      if (fault.kind == FaultKind::kLateFrames && Active(fault, t_ns) && IsFrame(*event)) {
        delay_s = std::max(delay_s, fault.magnitude);
      }
    }
    if (delay_s > 0.0) {
      const TimeNs release_ns = t_ns + FromSeconds(delay_s);
      const auto at = std::upper_bound(
          delayed_.begin(), delayed_.end(), release_ns,
          [](TimeNs t, const std::pair<TimeNs, SensorEvent>& d) { return t < d.first; });
      delayed_.insert(at, {release_ns, std::move(*event)});
      ++injected_.frames_delayed;
      continue;
    }
    return event;
  }
  return std::nullopt;
}

std::optional<SensorEvent> FaultInjectingSource::Next() {
  if (!lookahead_) lookahead_ = Pull();
  if (!delayed_.empty() && (!lookahead_ || delayed_.front().first <= EventTime(*lookahead_))) {
    SensorEvent event = std::move(delayed_.front().second);
    delayed_.erase(delayed_.begin());
    return event;
  }
  std::optional<SensorEvent> event = std::move(lookahead_);
  lookahead_.reset();
  return event;
}

}  // namespace parkslam::harness
