#include "parkslam/render/ground_raster.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"
#include "parkslam/common/seed_mix.h"
#include "parkslam/font/digit_font.h"

namespace parkslam::render {
namespace {

constexpr std::uint64_t kConcreteStreamTag = 0xc0c;
constexpr std::uint64_t kPaintStreamTag = 0x9a1;
constexpr std::uint64_t kDirtStreamTag = 0xd17;

// Sub-pixel precision of OpenCV's polygon filling: coordinates carry this
// many fractional bits.
constexpr int kDrawShift = 4;
constexpr double kDrawScale = 1 << kDrawShift;
static_assert(kDrawShift == font::kGlyphDrawShift, "IDs are drawn with the font's precision");

// Intermediate scale of the low-frequency concrete fields, in raster pixels.
constexpr int kShadingStepPx = 8;
constexpr double kShadingCellM = 4.0;
constexpr double kMottlingCellM = 0.5;

using Quad = std::array<Eigen::Vector2d, 4>;

// Map <-> raster pixel conversion shared by the drawing helpers.
struct RasterFrame {
  double min_x_m, max_y_m, resolution_m;

  Eigen::Vector2d Pixel(const Eigen::Vector2d& p_map) const {
    return {(p_map.x() - min_x_m) / resolution_m - 0.5, (max_y_m - p_map.y()) / resolution_m - 0.5};
  }
  // Fixed-point point for OpenCV drawing, relative to pixel `origin`.
  cv::Point Fixed(const Eigen::Vector2d& p_map, const cv::Point& origin) const {
    const Eigen::Vector2d px = Pixel(p_map);
    return {static_cast<int>(std::lround((px.x() - origin.x) * kDrawScale)),
            static_cast<int>(std::lround((px.y() - origin.y) * kDrawScale))};
  }
};

void FillQuad(const RasterFrame& frame, const Quad& quad_map, double value, const cv::Point& origin,
              cv::Mat* mask) {
  std::array<cv::Point, 4> pts;
  for (int i = 0; i < 4; ++i) pts[i] = frame.Fixed(quad_map[i], origin);
  cv::fillConvexPoly(*mask, pts.data(), 4, cv::Scalar(value), cv::LINE_AA, kDrawShift);
}

// A stripe of width w along p-q, extended by w/2 beyond both ends so that
// stripes meeting at a corner join squarely.
Quad Stripe(const Eigen::Vector2d& p, const Eigen::Vector2d& q, double w) {
  const Eigen::Vector2d d = (q - p).normalized();
  const Eigen::Vector2d n(-d.y(), d.x());
  const Eigen::Vector2d a = p - d * (w / 2), b = q + d * (w / 2);
  return {a - n * (w / 2), b - n * (w / 2), b + n * (w / 2), a + n * (w / 2)};
}

struct Bounds {
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  void Add(const Eigen::Vector2d& p) {
    min_x = std::min(min_x, p.x());
    min_y = std::min(min_y, p.y());
    max_x = std::max(max_x, p.x());
    max_y = std::max(max_y, p.y());
  }
};

Bounds WorldBounds(const sim::World& world) {
  Bounds b;
  b.Add({world.hall.min_x_m, world.hall.min_y_m});
  b.Add({world.hall.max_x_m, world.hall.max_y_m});
  for (const sim::WorldWall& w : world.walls) {
    b.Add(w.a_map);
    b.Add(w.b_map);
  }
  for (const sim::WorldSlot& s : world.slots) {
    for (const Eigen::Vector2d& c : s.corners_map) b.Add(c);
  }
  for (const sim::WorldPillar& p : world.pillars) {
    b.Add(p.center_map.array() - p.half_size_m);
    b.Add(p.center_map.array() + p.half_size_m);
  }
  return b;
}

// A smooth random field: uniform values in [-amplitude, amplitude] on a grid
// of cell_px pixels, interpolated bicubically to size.
cv::Mat SmoothField(const cv::Size& size, double cell_px, double amplitude, cv::RNG& rng) {
  const int gw = static_cast<int>(std::ceil(size.width / cell_px)) + 2;
  const int gh = static_cast<int>(std::ceil(size.height / cell_px)) + 2;
  cv::Mat grid(gh, gw, CV_32F);
  rng.fill(grid, cv::RNG::UNIFORM, -amplitude, amplitude);
  cv::Mat field;
  cv::resize(grid, field, size, 0, 0, cv::INTER_CUBIC);
  return field;
}

cv::Mat DrawConcrete(const cv::Size& size, const GroundRasterOptions& o, std::uint64_t seed) {
  cv::RNG rng(MixSeed(seed, kConcreteStreamTag));
  const cv::Size coarse((size.width + kShadingStepPx - 1) / kShadingStepPx,
                        (size.height + kShadingStepPx - 1) / kShadingStepPx);
  const double coarse_m = o.resolution_m * kShadingStepPx;
  cv::Mat field = SmoothField(coarse, kShadingCellM / coarse_m, o.shading_amplitude_grey, rng);
  field += SmoothField(coarse, kMottlingCellM / coarse_m, o.mottling_amplitude_grey, rng);
  field += o.concrete_grey;
  cv::Mat coarse_u8, image;
  field.convertTo(coarse_u8, CV_8U);
  cv::resize(coarse_u8, image, size, 0, 0, cv::INTER_LINEAR);
  if (o.grain_sigma_grey > 0.0) {
    cv::Mat grain(size, CV_8S);
    rng.fill(grain, cv::RNG::NORMAL, 0.0, o.grain_sigma_grey);
    cv::add(image, grain, image, cv::noArray(), CV_8U);
  }
  return image;
}

// Slot lines (paper III-A): both separating lines and the back line, plus
// the entrance stubs at corners 0 and 1.
void DrawSlotLines(const RasterFrame& frame, const sim::WorldSlot& slot,
                   const GroundRasterOptions& o, cv::Mat* paint) {
  const auto& c = slot.corners_map;
  const double w = o.line_width_m;
  const cv::Point origin(0, 0);
  FillQuad(frame, Stripe(c[1], c[2], w), 255, origin, paint);
  FillQuad(frame, Stripe(c[2], c[3], w), 255, origin, paint);
  FillQuad(frame, Stripe(c[3], c[0], w), 255, origin, paint);
  const double entrance_m = (c[1] - c[0]).norm();
  const double stub_m = std::min(o.entrance_stub_m, entrance_m / 2);
  if (stub_m > 0.0) {
    const Eigen::Vector2d e = (c[1] - c[0]) / entrance_m;
    FillQuad(frame, Stripe(c[0], c[0] + stub_m * e, w), 255, origin, paint);
    FillQuad(frame, Stripe(c[1], c[1] - stub_m * e, w), 255, origin, paint);
  }
}

// The painted ID in seven-segment digits; a worn ID faded and flaked.
void DrawId(const RasterFrame& frame, const sim::WorldSlot& slot, const GroundRasterOptions& o,
            Random& rng, cv::Mat* paint) {
  const IdPlacement id = PlaceId(slot, o);
  if (id.width_m <= 0.0) return;
  // The local mask covers the ID's box with a margin of a few pixels.
  const Quad box = {id.center_map - id.right_map * id.width_m / 2 - id.up_map * id.height_m / 2,
                    id.center_map + id.right_map * id.width_m / 2 - id.up_map * id.height_m / 2,
                    id.center_map + id.right_map * id.width_m / 2 + id.up_map * id.height_m / 2,
                    id.center_map - id.right_map * id.width_m / 2 + id.up_map * id.height_m / 2};
  Bounds px;
  for (const Eigen::Vector2d& p : box) px.Add(frame.Pixel(p));
  const cv::Rect roi = cv::Rect(cv::Point(static_cast<int>(std::floor(px.min_x)) - 3,
                                          static_cast<int>(std::floor(px.min_y)) - 3),
                                cv::Point(static_cast<int>(std::ceil(px.max_x)) + 4,
                                          static_cast<int>(std::ceil(px.max_y)) + 4)) &
                       cv::Rect(0, 0, paint->cols, paint->rows);
  if (roi.empty()) return;
  cv::Mat mask = cv::Mat::zeros(roi.size(), CV_8U);
  const double h = id.height_m, w = font::kDigitWidth * h, t = font::kDigitStroke * h;
  const Eigen::Vector2d foot_left = box[0];
  for (size_t k = 0; k < slot.painted_id.size(); ++k) {
    const char ch = slot.painted_id[k];
    if (ch < '0' || ch > '9') continue;
    const Eigen::Vector2d digit_origin =
        foot_left + id.right_map * (static_cast<double>(k) * (w + font::kDigitGap * h));
    // The shared font (font/digit_font.h), in the local mask's pixels.
    font::DrawSevenSegmentDigit(
        ch, h, t,
        [&](double x, double y) -> Eigen::Vector2d {
          const Eigen::Vector2d pixel =
              frame.Pixel(Eigen::Vector2d(digit_origin + id.right_map * x + id.up_map * y));
          return {pixel.x() - roi.x, pixel.y() - roi.y};
        },
        255, &mask);
  }
  if (!slot.id_legible) {
    mask *= o.worn_id_opacity;
    // Flakes: round holes until about the requested share of the box is gone.
    constexpr double kMeanFlakeRadiusM = 0.055;
    const double box_area_m2 = id.width_m * id.height_m;
    const int flakes = static_cast<int>(std::lround(o.worn_id_broken_fraction * box_area_m2 /
                                                    (kPi * kMeanFlakeRadiusM * kMeanFlakeRadiusM)));
    for (int f = 0; f < flakes; ++f) {
      const Eigen::Vector2d p = box[0] + id.right_map * rng.Uniform(0.0, id.width_m) +
                                id.up_map * rng.Uniform(0.0, id.height_m);
      const double r_px = rng.Uniform(0.03, 0.08) / o.resolution_m;
      const Eigen::Vector2d c = frame.Pixel(p);
      cv::circle(mask,
                 cv::Point(static_cast<int>(std::lround((c.x() - roi.x) * kDrawScale)),
                           static_cast<int>(std::lround((c.y() - roi.y) * kDrawScale))),
                 static_cast<int>(std::lround(r_px * kDrawScale)), cv::Scalar(0), cv::FILLED,
                 cv::LINE_AA, kDrawShift);
    }
  }
  cv::Mat target = (*paint)(roi);
  cv::max(target, mask, target);
}

// Paint over concrete: the paint keeps half of the concrete's texture.
void CompositePaint(const cv::Mat& paint, const GroundRasterOptions& o, cv::Mat* image) {
  const float paint_grey = static_cast<float>(o.paint_grey);
  const float concrete_grey = static_cast<float>(o.concrete_grey);
  for (int r = 0; r < image->rows; ++r) {
    const std::uint8_t* a = paint.ptr<std::uint8_t>(r);
    std::uint8_t* v = image->ptr<std::uint8_t>(r);
    for (int c = 0; c < image->cols; ++c) {
      if (a[c] == 0) continue;
      const float floor = v[c];
      const float painted = paint_grey + 0.5f * (floor - concrete_grey);
      const float out = floor + (painted - floor) * (static_cast<float>(a[c]) / 255.0f);
      v[c] = cv::saturate_cast<std::uint8_t>(out);
    }
  }
}

// Darkens the image by darkness * mask / 255 (multiplicatively) where a local
// mask drawn at pixel `origin` covers it.
void Darken(const cv::Mat& mask, const cv::Point& origin, double darkness, cv::Mat* image) {
  const cv::Rect roi = cv::Rect(origin, mask.size()) & cv::Rect(0, 0, image->cols, image->rows);
  for (int r = roi.y; r < roi.y + roi.height; ++r) {
    const float* m = mask.ptr<float>(r - origin.y);
    std::uint8_t* v = image->ptr<std::uint8_t>(r);
    for (int c = roi.x; c < roi.x + roi.width; ++c) {
      const float k = 1.0f - static_cast<float>(darkness) * m[c - origin.x];
      v[c] = cv::saturate_cast<std::uint8_t>(static_cast<float>(v[c]) * k);
    }
  }
}

Eigen::Vector2d SlotCentroid(const sim::WorldSlot& slot) {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : slot.corners_map) c += p / 4;
  return c;
}

// Oil stains: blurred dark ellipses, most of them where cars stand.
void DrawStains(const sim::World& world, const RasterFrame& frame, const GroundRasterOptions& o,
                Random& rng, cv::Mat* image) {
  const double area_m2 = world.floor_area_m2 > 0.0 ? world.floor_area_m2
                                                   : (world.hall.max_x_m - world.hall.min_x_m) *
                                                         (world.hall.max_y_m - world.hall.min_y_m);
  const int count = static_cast<int>(std::lround(area_m2 / 100.0 * o.stains_per_100m2));
  for (int k = 0; k < count; ++k) {
    Eigen::Vector2d p;
    if (!world.slots.empty() && rng.Bernoulli(0.7)) {
      const sim::WorldSlot& slot = world.slots[rng.Index(world.slots.size())];
      p = SlotCentroid(slot) + Eigen::Vector2d(rng.Uniform(-0.8, 0.8), rng.Uniform(-0.8, 0.8));
    } else {
      p = {rng.Uniform(world.hall.min_x_m, world.hall.max_x_m),
           rng.Uniform(world.hall.min_y_m, world.hall.max_y_m)};
    }
    const double rx_px = rng.Uniform(0.12, 0.5) / o.resolution_m;
    const double ry_px = rng.Uniform(0.12, 0.5) / o.resolution_m;
    const double angle_deg = rng.Uniform(0.0, 180.0);
    const double darkness = rng.Uniform(0.08, 0.3);
    const int half = static_cast<int>(std::ceil(1.6 * std::max(rx_px, ry_px)));
    cv::Mat mask = cv::Mat::zeros(2 * half + 1, 2 * half + 1, CV_32F);
    cv::ellipse(mask, cv::Point(half, half),
                cv::Size(static_cast<int>(rx_px), static_cast<int>(ry_px)), angle_deg, 0, 360,
                cv::Scalar(1.0), cv::FILLED);
    cv::GaussianBlur(mask, mask, cv::Size(0, 0), 0.25 * std::min(rx_px, ry_px));
    const Eigen::Vector2d c = frame.Pixel(p);
    Darken(mask,
           cv::Point(static_cast<int>(std::lround(c.x())) - half,
                     static_cast<int>(std::lround(c.y())) - half),
           darkness, image);
  }
}

// Tyre marks: two faint dark tracks curving from the aisle into a slot.
void DrawTyreMarks(const sim::World& world, const RasterFrame& frame, const GroundRasterOptions& o,
                   Random& rng, cv::Mat* image) {
  constexpr double kTrackHalfM = 0.8, kTyreWidthM = 0.18;
  const int count = static_cast<int>(
      std::lround(static_cast<double>(world.slots.size()) * o.tyre_marks_per_slot));
  for (int k = 0; k < count && !world.slots.empty(); ++k) {
    const sim::WorldSlot& slot = world.slots[rng.Index(world.slots.size())];
    const auto& c = slot.corners_map;
    const Eigen::Vector2d e = (c[1] - c[0]).normalized();
    const Eigen::Vector2d in(-e.y(), e.x());
    const Eigen::Vector2d mid = (c[0] + c[1]) / 2;
    const double side = rng.Bernoulli(0.5) ? 1.0 : -1.0;
    const std::array<Eigen::Vector2d, 3> bezier = {
        mid - 3.0 * in + side * rng.Uniform(2.0, 4.5) * e, mid - 0.8 * in,
        mid + rng.Uniform(1.5, 3.0) * in};
    const double darkness = rng.Uniform(0.03, 0.07);
    for (double track : {-kTrackHalfM, kTrackHalfM}) {
      std::vector<Eigen::Vector2d> pts;
      for (int i = 0; i <= 24; ++i) {
        const double u = i / 24.0;
        pts.push_back((1 - u) * (1 - u) * bezier[0] + 2 * u * (1 - u) * bezier[1] +
                      u * u * bezier[2] + track * e);
      }
      Bounds px;
      for (const Eigen::Vector2d& p : pts) px.Add(frame.Pixel(p));
      const int pad = static_cast<int>(std::ceil(kTyreWidthM / o.resolution_m)) + 4;
      const cv::Point origin(static_cast<int>(std::floor(px.min_x)) - pad,
                             static_cast<int>(std::floor(px.min_y)) - pad);
      cv::Mat mask = cv::Mat::zeros(static_cast<int>(px.max_y - px.min_y) + 2 * pad + 2,
                                    static_cast<int>(px.max_x - px.min_x) + 2 * pad + 2, CV_32F);
      std::vector<cv::Point> poly;
      for (const Eigen::Vector2d& p : pts) poly.push_back(frame.Fixed(p, origin));
      cv::polylines(mask, poly, false, cv::Scalar(1.0),
                    static_cast<int>(std::lround(kTyreWidthM / o.resolution_m)), cv::LINE_AA,
                    kDrawShift);
      cv::GaussianBlur(mask, mask, cv::Size(0, 0), 2.5);
      Darken(mask, origin, darkness, image);
    }
  }
}

// Walls and pillars as black footprints.
void DrawObstacles(const sim::World& world, const RasterFrame& frame, const GroundRasterOptions& o,
                   cv::Mat* image) {
  const cv::Point origin(0, 0);
  for (const sim::WorldWall& wall : world.walls) {
    FillQuad(frame, Stripe(wall.a_map, wall.b_map, o.wall_thickness_m), 0, origin, image);
  }
  for (const sim::WorldPillar& p : world.pillars) {
    const double h = p.half_size_m;
    const Eigen::Vector2d c = p.center_map;
    FillQuad(frame,
             {c + Eigen::Vector2d(-h, -h), c + Eigen::Vector2d(h, -h), c + Eigen::Vector2d(h, h),
              c + Eigen::Vector2d(-h, h)},
             0, origin, image);
  }
}

}  // namespace

bool GroundRasterOptions::IsValid(std::string* error) const {
  const auto fail = [error](const char* what) {
    if (error != nullptr) *error = what;
    return false;
  };
  if (!(resolution_m >= 0.005 && resolution_m <= 0.2))
    return fail("resolution_m must be in [0.005, 0.2]");
  if (!(margin_m >= 0.0)) return fail("margin_m must be non-negative");
  if (!(concrete_grey >= 0.0 && concrete_grey <= 255.0))
    return fail("concrete_grey must be in [0, 255]");
  if (!(paint_grey >= 0.0 && paint_grey <= 255.0)) return fail("paint_grey must be in [0, 255]");
  if (!(shading_amplitude_grey >= 0.0 && mottling_amplitude_grey >= 0.0 &&
        grain_sigma_grey >= 0.0)) {
    return fail("concrete amplitudes must be non-negative");
  }
  if (!(line_width_m > 0.0 && line_width_m < 1.0)) return fail("line_width_m must be in (0, 1)");
  if (!(entrance_stub_m >= 0.0)) return fail("entrance_stub_m must be non-negative");
  if (!(id_height_m > 0.0 && id_height_m < 3.0)) return fail("id_height_m must be in (0, 3)");
  if (!(id_setback_m >= 0.0)) return fail("id_setback_m must be non-negative");
  if (!(worn_id_opacity >= 0.0 && worn_id_opacity <= 1.0))
    return fail("worn_id_opacity must be in [0, 1]");
  if (!(worn_id_broken_fraction >= 0.0 && worn_id_broken_fraction <= 1.0)) {
    return fail("worn_id_broken_fraction must be in [0, 1]");
  }
  if (!(stains_per_100m2 >= 0.0 && tyre_marks_per_slot >= 0.0))
    return fail("dirt rates must be non-negative");
  if (!(wall_thickness_m > 0.0)) return fail("wall_thickness_m must be positive");
  return true;
}

IdPlacement PlaceId(const sim::WorldSlot& slot, const GroundRasterOptions& options) {
  const auto& c = slot.corners_map;
  IdPlacement id;
  id.up_map = ((c[2] + c[3]) / 2 - (c[0] + c[1]) / 2).normalized();
  id.right_map = Eigen::Vector2d(id.up_map.y(), -id.up_map.x());
  id.height_m = options.id_height_m;
  const double n = static_cast<double>(slot.painted_id.size());
  id.width_m =
      n > 0 ? options.id_height_m * (n * font::kDigitWidth + (n - 1) * font::kDigitGap) : 0.0;
  id.center_map = (c[0] + c[1]) / 2 + id.up_map * (options.id_setback_m + id.height_m / 2);
  return id;
}

GroundRaster::GroundRaster(const sim::World& world, const GroundRasterOptions& options,
                           std::uint64_t seed)
    : options_(options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("GroundRasterOptions: " + error);
  const Bounds b = WorldBounds(world);
  const double res = options.resolution_m;
  min_x_m_ = b.min_x - options.margin_m;
  max_y_m_ = b.max_y + options.margin_m;
  const cv::Size size(static_cast<int>(std::ceil((b.max_x + options.margin_m - min_x_m_) / res)),
                      static_cast<int>(std::ceil((max_y_m_ - (b.min_y - options.margin_m)) / res)));
  const RasterFrame frame{min_x_m_, max_y_m_, res};

  image_ = DrawConcrete(size, options, seed);

  cv::Mat paint = cv::Mat::zeros(size, CV_8U);
  Random paint_rng = Random::Derive(seed, kPaintStreamTag);
  for (const sim::WorldSlot& slot : world.slots) {
    DrawSlotLines(frame, slot, options, &paint);
    DrawId(frame, slot, options, paint_rng, &paint);
  }
  CompositePaint(paint, options, &image_);

  if (options.stains) {
    Random dirt_rng = Random::Derive(seed, kDirtStreamTag);
    DrawStains(world, frame, options, dirt_rng, &image_);
    DrawTyreMarks(world, frame, options, dirt_rng, &image_);
  }
  DrawObstacles(world, frame, options, &image_);
}

Eigen::Vector2d GroundRaster::PixelOf(const Eigen::Vector2d& p_map) const {
  return RasterFrame{min_x_m_, max_y_m_, options_.resolution_m}.Pixel(p_map);
}

Eigen::Vector2d GroundRaster::MapOf(const Eigen::Vector2d& pixel) const {
  const double res = options_.resolution_m;
  return {min_x_m_ + (pixel.x() + 0.5) * res, max_y_m_ - (pixel.y() + 0.5) * res};
}

std::uint8_t GroundRaster::At(const Eigen::Vector2d& p_map) const {
  const Eigen::Vector2d px = PixelOf(p_map);
  const long c = std::lround(px.x()), r = std::lround(px.y());
  if (c < 0 || r < 0 || c >= image_.cols || r >= image_.rows) return 0;
  return image_.at<std::uint8_t>(static_cast<int>(r), static_cast<int>(c));
}

}  // namespace parkslam::render
