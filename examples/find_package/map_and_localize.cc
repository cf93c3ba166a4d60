// Maps a row of three slots from a short straight drive, live, then
// localizes a second drive on that map: the core's live API (live::
// LiveSystem), fed event by event as a car's software would, through the
// installed library alone.
// Prints the map and the last pose; exits non-zero when either is off.

#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "parkslam/live/live_system.h"

namespace {

using namespace parkslam;

constexpr TimeNs kMs = 1'000'000;

// Slot s: entrance along y = 3 from x = 5 + 2.5 s, 5.3 m deep.
std::array<Eigen::Vector2d, 4> SlotCorners(int s) {
  const double x = 5.0 + 2.5 * s;
  return {Eigen::Vector2d(x, 3.0), Eigen::Vector2d(x + 2.5, 3.0), Eigen::Vector2d(x + 2.5, 8.3),
          Eigen::Vector2d(x, 8.3)};
}

// A drive along +x at 1 m/s from x = 0 to 15 (the wheels and the gyro
// exact): IMU at 100 Hz, wheel speed and steering at 50 Hz, a top view at
// 10 Hz seeing the slots whose entrance lies within 5 m.
void Drive(TimeNs t0, const std::function<void(const SensorEvent&)>& feed) {
  for (int i = 0; i <= 1500; ++i) {
    const TimeNs t = t0 + i * 10 * kMs;
    const double x = 0.01 * i;
    feed(ImuSample{t, 0.0, 0.0});
    if (i % 2 == 0) {
      feed(WheelSpeed{t, 1.0});
      feed(SteeringAngle{t, 0.0});
    }
    if (i % 10 != 5) continue;
    SlotObservationFrame frame;
    frame.t_ns = t;
    for (int s = 0; s < 3; ++s) {
      const std::array<Eigen::Vector2d, 4> corners = SlotCorners(s);
      if (std::abs(corners[0].x() - x) > 5.0 || std::abs(corners[1].x() - x) > 5.0) continue;
      SlotObservation obs;
      for (int j = 0; j < 4; ++j) obs.corners_vehicle[j] = corners[j] - Eigen::Vector2d(x, 0.0);
      obs.corner_sigma_m = 0.03;
      for (const char c : std::to_string(21 + s)) obs.id.digits.push_back({{{c, 0.9}}});
      frame.slots.push_back(obs);
    }
    feed(frame);
  }
}

}  // namespace

int main() {
  // Mapping live, from a known start: the online mapper behind the live API.
  live::LiveOptions options;
  live::LiveSystem mapping(nullptr, options, SE2());
  Drive(0, [&](const SensorEvent& e) { mapping.Process(e); });
  mapping.Finish();
  const SemanticMap map = mapping.Map();
  for (const MapSlot& slot : map.slots) {
    std::printf("slot %s at (%.2f, %.2f)\n", slot.id.c_str(), slot.corners_map[0].x(),
                slot.corners_map[0].y());
  }

  // Localizing live on that map: a pose at every camera frame.
  live::LiveSystem localizing(map, nullptr, options, SE2());
  std::optional<SE2> last;
  Drive(100'000 * kMs, [&](const SensorEvent& e) {
    localizing.Process(e);
    for (const auto& estimate : localizing.TakeEstimates()) last = estimate.T_map_vehicle;
  });
  localizing.Finish();
  if (!last) {
    std::printf("no pose\n");
    return 1;
  }
  const double error_m = std::hypot(last->x() - 14.95, last->y());
  std::printf("last pose (%.3f, %.3f), %.3f m from the truth\n", last->x(), last->y(), error_m);
  return map.slots.size() == 3 && error_m < 0.1 ? 0 : 1;
}
