#include "parkslam/render/light_field.h"

#include <algorithm>
#include <cmath>

namespace parkslam::render {
namespace {

constexpr double kCellM = 0.25;
constexpr double kGlowDecayM = 5.0;
constexpr float kLampHalfLengthM = 0.6f, kLampHalfWidthM = 0.06f;
constexpr int kLampReach = 4;  // lamps counted on either side, in spacings

}  // namespace

std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> WallOpenings(const sim::World& world) {
  std::vector<Eigen::Vector2d> ends;
  for (const sim::WorldWall& w : world.walls) {
    ends.push_back(w.a_map);
    ends.push_back(w.b_map);
  }
  std::vector<Eigen::Vector2d> free_ends;
  for (size_t i = 0; i < ends.size(); ++i) {
    bool joined = false;
    for (size_t j = 0; j < ends.size() && !joined; ++j) {
      joined = j != i && (ends[i] - ends[j]).norm() < 0.01;
    }
    if (!joined) free_ends.push_back(ends[i]);
  }
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> openings;
  for (size_t i = 0; i < free_ends.size(); ++i) {
    size_t nearest = i;
    double best = 10.0;
    for (size_t j = 0; j < free_ends.size(); ++j) {
      const double d = (free_ends[i] - free_ends[j]).norm();
      if (j != i && d < best) {
        best = d;
        nearest = j;
      }
    }
    if (nearest > i) openings.emplace_back(free_ends[i], free_ends[nearest]);
  }
  return openings;
}

LightField::LightField(const sim::World& world, double min_x_m, double max_y_m, double width_m,
                       double height_m, const LightFieldOptions& options)
    : spacing_m_(static_cast<float>(options.lamp_spacing_m)),
      inv_spacing_(static_cast<float>(1.0 / options.lamp_spacing_m)),
      lamp_x0_m_(static_cast<float>(world.hall.min_x_m + options.lamp_spacing_m / 2)),
      lamp_y0_m_(static_cast<float>(world.hall.min_y_m + options.lamp_spacing_m / 2)),
      min_x_m_(min_x_m),
      max_y_m_(max_y_m) {
  grid_.create(static_cast<int>(std::ceil(height_m / kCellM)) + 1,
               static_cast<int>(std::ceil(width_m / kCellM)) + 1, CV_32F);
  // Irradiance from each lamp at height h: cos(theta) / r^2 ~ (h / r)^3.
  const double h = options.lamp_height_m, spacing = options.lamp_spacing_m;
  double hall_sum = 0.0;
  int hall_count = 0;
  for (int r = 0; r < grid_.rows; ++r) {
    for (int c = 0; c < grid_.cols; ++c) {
      const double x = min_x_m_ + (c + 0.5) * kCellM;
      const double y = max_y_m_ - (r + 0.5) * kCellM;
      const int i0 = static_cast<int>(std::lround((x - lamp_x0_m_) / spacing));
      const int j0 = static_cast<int>(std::lround((y - lamp_y0_m_) / spacing));
      double sum = 0.0;
      for (int i = i0 - kLampReach; i <= i0 + kLampReach; ++i) {
        for (int j = j0 - kLampReach; j <= j0 + kLampReach; ++j) {
          const double dx = x - (lamp_x0_m_ + i * spacing);
          const double dy = y - (lamp_y0_m_ + j * spacing);
          const double q = h * h / (h * h + dx * dx + dy * dy);
          sum += q * std::sqrt(q);
        }
      }
      grid_.at<float>(r, c) = static_cast<float>(sum);
      if (world.hall.Contains({x, y})) {
        hall_sum += sum;
        ++hall_count;
      }
    }
  }
  const double mean = hall_count > 0 ? hall_sum / hall_count : 1.0;
  std::vector<Eigen::Vector2d> openings;
  for (const auto& [a, b] : WallOpenings(world)) openings.push_back((a + b) / 2);
  for (int r = 0; r < grid_.rows; ++r) {
    for (int c = 0; c < grid_.cols; ++c) {
      const Eigen::Vector2d p(min_x_m_ + (c + 0.5) * kCellM, max_y_m_ - (r + 0.5) * kCellM);
      double light =
          (1.0 - options.uneven_light) + options.uneven_light * grid_.at<float>(r, c) / mean;
      for (const Eigen::Vector2d& o : openings) {
        light *= 1.0 +
                 3.0 * options.overexposure_near_entrance * std::exp(-(p - o).norm() / kGlowDecayM);
      }
      grid_.at<float>(r, c) = static_cast<float>(light);
    }
  }
}

float LightField::At(double x_m, double y_m) const {
  const double gx = std::clamp((x_m - min_x_m_) / kCellM - 0.5, 0.0, grid_.cols - 1.001);
  const double gy = std::clamp((max_y_m_ - y_m) / kCellM - 0.5, 0.0, grid_.rows - 1.001);
  const int ix = static_cast<int>(gx), iy = static_cast<int>(gy);
  const float wx = static_cast<float>(gx - ix), wy = static_cast<float>(gy - iy);
  const float* r0 = grid_.ptr<float>(iy) + ix;
  const float* r1 = grid_.ptr<float>(iy + 1) + ix;
  const float top = r0[0] + (r0[1] - r0[0]) * wx;
  const float bottom = r1[0] + (r1[1] - r1[0]) * wx;
  return top + (bottom - top) * wy;
}

bool LightField::IsLamp(float x_m, float y_m) const {
  // Offset from the nearest lamp centre, the floor done by hand: a call to
  // std::floor per pixel costs more than the rest of the test.
  const auto offset = [this](float v) {
    const float cells = v * inv_spacing_ + 0.5f;
    int k = static_cast<int>(cells);
    if (static_cast<float>(k) > cells) --k;
    return std::abs(v - static_cast<float>(k) * spacing_m_);
  };
  return offset(x_m - lamp_x0_m_) < kLampHalfLengthM && offset(y_m - lamp_y0_m_) < kLampHalfWidthM;
}

}  // namespace parkslam::render
