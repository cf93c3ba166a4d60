#include "parkslam/io/pose_text.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "parkslam/common/plausible_ranges.h"

namespace parkslam::io {

SE2 ParsePose(const std::string& text, const std::string& name) {
  double values[3];
  size_t start = 0;
  for (int i = 0; i < 3; ++i) {
    const size_t end = text.find(',', start);
    const std::string part = text.substr(start, end == std::string::npos ? end : end - start);
    try {
      size_t used = 0;
      values[i] = std::stod(part, &used);
      if (used != part.size() || !std::isfinite(values[i])) throw std::invalid_argument(part);
    } catch (const std::exception&) {
      throw std::invalid_argument(name + ": expected x,y,yaw (metres, radians), got '" + text +
                                  "'");
    }
    if ((end == std::string::npos) != (i == 2)) {
      throw std::invalid_argument(name + ": expected x,y,yaw (metres, radians), got '" + text +
                                  "'");
    }
    start = end + 1;
  }
  // The limits of common/plausible_ranges.h, as for a pose read from a file.
  const char* const kNames[3] = {"x", "y", "yaw"};
  const double kLimits[3] = {kMaxCoordinate_m, kMaxCoordinate_m, kMaxAngle_rad};
  const char* const kUnits[3] = {"m", "m", "rad"};
  for (int i = 0; i < 3; ++i) {
    if (std::abs(values[i]) > kLimits[i]) {
      char value[32];
      *std::to_chars(value, value + sizeof value - 1, values[i]).ptr = '\0';
      char limit[32];
      std::snprintf(limit, sizeof limit, "%g", kLimits[i]);
      throw std::invalid_argument(name + ": " + kNames[i] + " " + value +
                                  " is beyond the plausible " + limit + " " + kUnits[i]);
    }
  }
  return SE2(values[0], values[1], values[2]);
}

SE2 ParseStartPose(const std::string& text, const SemanticMap& map, const std::string& name,
                   const std::string& map_name) {
  if (text != "entrance") return ParsePose(text, name);
  if (!map.entrance) {
    throw std::invalid_argument(name + " entrance: " + map_name +
                                " has no entrance (a map made before maps kept where their "
                                "drive began); give x,y,yaw");
  }
  return *map.entrance;
}

}  // namespace parkslam::io
