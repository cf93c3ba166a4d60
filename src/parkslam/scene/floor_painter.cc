#include "parkslam/scene/floor_painter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"
#include "parkslam/common/seed_mix.h"

namespace parkslam::scene {
namespace {

constexpr double kLightGridM = 0.5;
constexpr double kLightHalfExtentM = 24.0;  // the light grid covers +-this around the car
constexpr int kGrainBankSize = 1024;
constexpr int kShift = 4;  // sub-pixel bits of the polygon filler
constexpr float kSubPixel = 1 << kShift;

float Hash01(std::uint64_t seed, std::int64_t a, std::int64_t b) {
  const std::uint64_t h =
      MixSeed(seed, static_cast<std::uint64_t>(a) * 0x1f1f1f1full + static_cast<std::uint64_t>(b));
  return static_cast<float>(h >> 40) * (1.0f / 16777216.0f);
}

// Smooth value noise in about [-1, 1] over `size`, varying over cell_px.
cv::Mat SmoothNoise(cv::Size size, double cell_px, cv::RNG& rng) {
  const int w = std::max(2, static_cast<int>(std::ceil(size.width / cell_px)) + 2);
  const int h = std::max(2, static_cast<int>(std::ceil(size.height / cell_px)) + 2);
  cv::Mat small(h, w, CV_32F);
  rng.fill(small, cv::RNG::UNIFORM, -1.0, 1.0);
  cv::Mat big;
  cv::resize(small, big, cv::Size(static_cast<int>(w * cell_px), static_cast<int>(h * cell_px)), 0,
             0, cell_px > 12 ? cv::INTER_LINEAR : cv::INTER_CUBIC);
  return big(cv::Rect(static_cast<int>(cell_px / 2), static_cast<int>(cell_px / 2), size.width,
                      size.height))
      .clone();
}

// A window of `bank` (window_size, clipped to the bank) at a random place,
// resized to `size` with `interpolation` where the two differ: noise banks
// made once stand in for fresh noise per scene.
cv::Mat BankWindow(const cv::Mat& bank, cv::Size window_size, cv::Size size, cv::RNG& rng,
                   int interpolation) {
  if (window_size == size && (size.width > bank.cols || size.height > bank.rows)) {
    // Larger than the bank (a whole lot's floor): the bank tiled from a
    // random place, at its own scale.
    const int x0 = rng.uniform(0, bank.cols), y0 = rng.uniform(0, bank.rows);
    cv::Mat tiled;
    cv::repeat(bank, size.height / bank.rows + 2, size.width / bank.cols + 2, tiled);
    return tiled(cv::Rect(x0, y0, size.width, size.height)).clone();
  }
  const int w = std::min(window_size.width, bank.cols);
  const int h = std::min(window_size.height, bank.rows);
  const cv::Rect window(rng.uniform(0, bank.cols - w + 1), rng.uniform(0, bank.rows - h + 1), w, h);
  if (window.size() == size) return bank(window);
  cv::Mat resized;
  cv::resize(bank(window), resized, size, 0, 0, interpolation);
  return resized;
}

cv::Point Fixed(const Eigen::Vector2d& px) {
  return {static_cast<int>(std::lround((px.x()) * kSubPixel)),
          static_cast<int>(std::lround((px.y()) * kSubPixel))};
}

// The pixel rectangle holding points (with a margin), clipped to the image.
cv::Rect Bounds(const std::vector<Eigen::Vector2d>& px, int margin, cv::Size size) {
  double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
  for (const auto& p : px) {
    x0 = std::min(x0, p.x());
    y0 = std::min(y0, p.y());
    x1 = std::max(x1, p.x());
    y1 = std::max(y1, p.y());
  }
  const cv::Rect r(static_cast<int>(std::floor(x0)) - margin,
                   static_cast<int>(std::floor(y0)) - margin,
                   static_cast<int>(std::ceil(x1 - x0)) + 2 * margin + 2,
                   static_cast<int>(std::ceil(y1 - y0)) + 2 * margin + 2);
  return r & cv::Rect(0, 0, size.width, size.height);
}

// Fills a polygon (canvas pixels) into an 8-bit mask covering roi.
void FillPolygon(const std::vector<Eigen::Vector2d>& px, const cv::Rect& roi, cv::Mat* mask,
                 int value = 255) {
  std::vector<cv::Point> pts;
  pts.reserve(px.size());
  for (const auto& p : px) pts.push_back(Fixed(p - Eigen::Vector2d(roi.x, roi.y)));
  cv::fillConvexPoly(*mask, pts, cv::Scalar(value), cv::LINE_AA, kShift);
}

std::vector<Eigen::Vector2d> StrokePolygon(const Canvas& c, const Eigen::Vector2d& a,
                                           const Eigen::Vector2d& b, double width_m) {
  Eigen::Vector2d d = b - a;
  const double len = d.norm();
  d = len > 1e-9 ? Eigen::Vector2d(d / len) : Eigen::Vector2d::UnitX();
  const Eigen::Vector2d n(-d.y(), d.x());
  const Eigen::Vector2d h = n * (width_m / 2);
  return {c.PixelOf(a + h), c.PixelOf(b + h), c.PixelOf(b - h), c.PixelOf(a - h)};
}

std::vector<Eigen::Vector2d> BoxPolygon(const Canvas& c, const Eigen::Vector2d& center, double yaw,
                                        double half_l, double half_w) {
  const Eigen::Vector2d ax(std::cos(yaw), std::sin(yaw)), ay(-ax.y(), ax.x());
  return {
      c.PixelOf(center + ax * half_l + ay * half_w), c.PixelOf(center - ax * half_l + ay * half_w),
      c.PixelOf(center - ax * half_l - ay * half_w), c.PixelOf(center + ax * half_l - ay * half_w)};
}

// img = img (1 - a) + colour a over roi, a = mask / 255 x scale (x weight).
void Blend(cv::Mat& img, const cv::Rect& roi, const cv::Mat& mask8, const Colour& colour,
           float scale, const cv::Mat* weight = nullptr) {
  for (int r = 0; r < roi.height; ++r) {
    cv::Vec3f* row = img.ptr<cv::Vec3f>(roi.y + r) + roi.x;
    const std::uint8_t* m = mask8.ptr<std::uint8_t>(r);
    const float* w = weight != nullptr ? weight->ptr<float>(roi.y + r) + roi.x : nullptr;
    for (int col = 0; col < roi.width; ++col) {
      if (m[col] == 0) continue;
      float a = m[col] * (scale / 255.0f);
      if (w != nullptr) a *= w[col];
      a = std::clamp(a, 0.0f, 1.0f);
      cv::Vec3f& p = row[col];
      for (int k = 0; k < 3; ++k) p[k] += (colour[k] - p[k]) * a;
    }
  }
}

// img *= 1 - depth x mask / 255 x (per channel factor) over roi.
void Darken(cv::Mat& img, const cv::Rect& roi, const cv::Mat& mask8, float depth,
            const Colour& channel = Colour(1, 1, 1)) {
  for (int r = 0; r < roi.height; ++r) {
    cv::Vec3f* row = img.ptr<cv::Vec3f>(roi.y + r) + roi.x;
    const std::uint8_t* m = mask8.ptr<std::uint8_t>(r);
    for (int col = 0; col < roi.width; ++col) {
      if (m[col] == 0) continue;
      const float a = m[col] * (depth / 255.0f);
      for (int k = 0; k < 3; ++k) row[col][k] *= 1.0f - a * channel[k];
    }
  }
}

class Painter {
 public:
  Painter(const Scene& scene, const LightMap& light, const FloorPainterOptions& options,
          FontBook* fonts, Canvas* canvas)
      : scene_(scene),
        light_(light),
        options_(options),
        fonts_(fonts),
        c_(*canvas),
        rng_(MixSeed(scene.seed, 0xf100)) {
    img_ = cv::Mat(canvas->bgr.size(), CV_32FC3);
  }

  void Run(cv::Mat* slot_paint) {
    Material();
    Verge();
    if (options_.dirt) {
      for (const Decal& d : scene_.decals) UnderPaint(d);
    }
    wear_ = 0.5f + 0.3f * SmoothNoise(img_.size(), 0.3 / c_.resolution_m, rng_) +
            0.2f * SmoothNoise(img_.size(), std::max(2.0, 0.06 / c_.resolution_m), rng_);
    for (const Decal& d : scene_.decals) PaintedDecal(d);
    if (slot_paint != nullptr) *slot_paint = cv::Mat(img_.size(), CV_8UC1, cv::Scalar(0));
    for (const Stroke& s : scene_.strokes) StrokeOn(s, slot_paint);
    if (options_.draw_text && fonts_ != nullptr) {
      for (const FloorText& t : scene_.texts) TextOn(t);
    }
    for (const Decal& d : scene_.decals) OnTop(d);
    Shadows();
    LightInto8Bit();
  }

 private:
  double Px(double metres) const { return metres / c_.resolution_m; }

  // Per-pixel standard normal noise: a window of a fixed bank at a random
  // place (drawing fresh normals for every pixel of every scene is slow).
  cv::Mat Grain(cv::Size size) {
    static const cv::Mat bank = [] {
      cv::Mat b(kGrainBankSize, kGrainBankSize, CV_32F);
      cv::RNG rng(0x9a1);
      rng.fill(b, cv::RNG::NORMAL, 0.0, 1.0);
      return b;
    }();
    return BankWindow(bank, size, size, rng_, cv::INTER_NEAREST);
  }

  void Material() {
    const Floor& f = scene_.floor;
    const cv::Size size = img_.size();
    // Octaves above 0.2 m are summed on a coarse grid (and its colour drift
    // beside them), then enlarged once; the grain is added per pixel.
    const double coarse_m = std::max(c_.resolution_m, 0.1);
    const cv::Size coarse(
        static_cast<int>(std::ceil(size.width * c_.resolution_m / coarse_m)) + 1,
        static_cast<int>(std::ceil(size.height * c_.resolution_m / coarse_m)) + 1);
    cv::Mat low = cv::Mat::zeros(coarse, CV_32F);
    cv::Mat lum = cv::Mat::zeros(size, CV_32F);
    const auto add_noise = [&](double cell_m, double amplitude) {
      if (amplitude <= 0) return;
      if (Px(cell_m) < 1.5) {
        cv::scaleAdd(Grain(size), amplitude, lum, lum);
      } else {
        low += static_cast<float>(amplitude) *
               SmoothNoise(coarse, std::max(1.0, cell_m / coarse_m), rng_);
      }
    };
    add_noise(4.0, 14.0 * f.blotches);
    add_noise(1.0, 6.0 * f.blotches);
    switch (f.material) {
      case FloorMaterial::kConcrete:
        add_noise(0.25, 4.0 * f.texture);
        add_noise(0.01, 2.0 * f.texture);
        break;
      case FloorMaterial::kEpoxy:
        add_noise(0.5, 2.0 * f.texture);
        add_noise(0.01, 1.5 * f.texture);
        break;
      case FloorMaterial::kAsphalt: {
        add_noise(0.01, 6.0 * f.texture);
        cv::Mat speck;
        cv::threshold(Grain(size), speck, 1.9, 30.0 * f.texture, cv::THRESH_BINARY);
        lum += speck;
        break;
      }
      case FloorMaterial::kBricks:
      case FloorMaterial::kTiles:
        add_noise(0.01, 2.0 * f.texture);
        break;
    }
    MidScaleTexture(f, &lum);
    // Colour: the base plus a little metre-scale chroma drift.
    cv::Mat layers[3] = {low, 4.0f * SmoothNoise(coarse, 3.0 / coarse_m, rng_),
                         4.0f * SmoothNoise(coarse, 3.0 / coarse_m, rng_)};
    cv::Mat merged, enlarged;
    cv::merge(layers, 3, merged);
    const double scale = coarse_m / c_.resolution_m;
    cv::resize(
        merged, enlarged,
        cv::Size(static_cast<int>(coarse.width * scale), static_cast<int>(coarse.height * scale)),
        0, 0, cv::INTER_LINEAR);
    cv::Mat smooth[3];
    cv::split(enlarged(cv::Rect(0, 0, size.width, size.height)), smooth);
    lum += smooth[0];
    const cv::Mat& chroma_b = smooth[1];
    const cv::Mat& chroma_r = smooth[2];
    const bool pattern =
        f.material == FloorMaterial::kBricks || f.material == FloorMaterial::kTiles;
    const double cy = std::cos(f.pattern_yaw_rad), sy = std::sin(f.pattern_yaw_rad);
    const std::uint64_t pseed = MixSeed(scene_.seed, 0xb41c);
    const double unit = f.unit_m;
    const double joint_m = f.material == FloorMaterial::kBricks ? 0.012 : 0.008;
    const float scale_base = 1.0f / 128.0f;
    for (int r = 0; r < size.height; ++r) {
      cv::Vec3f* out = img_.ptr<cv::Vec3f>(r);
      const float* l = lum.ptr<float>(r);
      const float* cb = chroma_b.ptr<float>(r);
      const float* cr = chroma_r.ptr<float>(r);
      const double y = c_.max_y_m - (r + 0.5) * c_.resolution_m;
      for (int col = 0; col < size.width; ++col) {
        Colour base = f.base;
        float joint = 0.0f;
        if (pattern) {
          const double x = c_.min_x_m + (col + 0.5) * c_.resolution_m;
          const double u = cy * x + sy * y, v = -sy * x + cy * y;
          double bu = unit, bv = f.material == FloorMaterial::kBricks ? unit / 2 : unit;
          double uu = u, vv = v;
          if (f.herringbone) {
            // Basket weave: 2 x 2 blocks alternate the bricks' direction.
            const auto block =
                static_cast<std::int64_t>(std::floor(u / unit) + std::floor(v / unit));
            if (block % 2 != 0) std::swap(uu, vv);
            bv = unit / 2;
          }
          const double row = std::floor(vv / bv);
          const double offset = f.material == FloorMaterial::kBricks && !f.herringbone &&
                                        static_cast<std::int64_t>(row) % 2 != 0
                                    ? bu / 2
                                    : 0.0;
          const double fu = uu + offset - std::floor((uu + offset) / bu) * bu;
          const double fv = vv - row * bv;
          const double du = std::min(fu, bu - fu), dv = std::min(fv, bv - fv);
          const double d = std::min(du, dv);
          joint =
              static_cast<float>(std::clamp(1.0 - (d - joint_m / 2) / c_.resolution_m, 0.0, 1.0));
          const float spread = f.material == FloorMaterial::kBricks ? 0.2f : 0.08f;
          const float tone =
              1.0f - spread / 2 +
              spread * Hash01(pseed, static_cast<std::int64_t>(row),
                              static_cast<std::int64_t>(std::floor((uu + offset) / bu)));
          base = base * tone;
        }
        const float k = 1.0f + l[col] * scale_base;
        cv::Vec3f& p = out[col];
        p[0] = base[0] * k + cb[col];
        p[1] = base[1] * k;
        p[2] = base[2] * k + cr[col];
        if (joint > 0.0f) {
          for (int c = 0; c < 3; ++c) p[c] += (f.joint[c] * k - p[c]) * joint;
        }
      }
    }
  }

  // Texture at 4-10 cm (aggregate, pores, scuffs, the grain of asphalt),
  // with darker sharp-edged specks: between the per-pixel grain and the
  // 0.25 m octave the floors had nothing, and the real ps2.0 views carry
  // about 1.4 times the rendered energy in that band (difference of
  // Gaussians at 1.5 and 3 px of the 600 px view, median over the floor;
  // docs/training_data.md). A window of a bank made once at 2 cm a pixel,
  // as for the grain; its own stream, so the rest of the floor draws as
  // before.
  void MidScaleTexture(const Floor& f, cv::Mat* lum) {
    constexpr double kBankResolutionM = 0.02;
    static const cv::Mat bank = [] {
      cv::RNG rng(0x3a66);
      const cv::Size size(kGrainBankSize, kGrainBankSize);
      cv::Mat b = SmoothNoise(size, 0.04 / kBankResolutionM, rng) +
                  0.8 * SmoothNoise(size, 0.1 / kBankResolutionM, rng);
      cv::Mat specks;
      cv::threshold(SmoothNoise(size, 0.05 / kBankResolutionM, rng), specks, 0.7, -2.5,
                    cv::THRESH_BINARY);
      return cv::Mat(b + specks);
    }();
    // In grey levels of 128, as the octaves above, by FloorMaterial:
    // concrete, epoxy, asphalt, bricks, tiles.
    constexpr std::array<double, 5> kAmplitude = {5.0, 1.5, 4.0, 3.0, 2.0};
    const double amplitude = kAmplitude[static_cast<size_t>(f.material)] * f.texture;
    // Coarse canvases (the far level) hold this band in their own octaves.
    if (amplitude <= 0.0 || c_.resolution_m >= 0.1) return;
    const cv::Size size = lum->size();
    const double ratio = c_.resolution_m / kBankResolutionM;
    const cv::Size window(static_cast<int>(std::ceil(size.width * ratio)),
                          static_cast<int>(std::ceil(size.height * ratio)));
    cv::RNG rng(MixSeed(scene_.seed, 0x3a66));
    cv::scaleAdd(BankWindow(bank, window, size, rng, cv::INTER_AREA), amplitude, *lum, *lum);
  }

  void Verge() {
    const Floor& f = scene_.floor;
    if (!f.verge) return;
    const cv::Size size = img_.size();
    const cv::Mat fine = SmoothNoise(size, std::max(1.5, Px(0.03)), rng_);
    const cv::Mat mid = SmoothNoise(size, Px(0.4), rng_);
    cv::Mat grain(size, CV_32F);
    rng_.fill(grain, cv::RNG::NORMAL, 0.0, 1.0);
    const Colour grass =
        Colour(50, 125, 85) * static_cast<float>(0.7 + 0.5 * rng_.uniform(0.0, 1.0));
    const Colour dry(70, 130, 150);
    const Colour kerb(175, 178, 178);
    const double kerb_m = f.kerb ? 0.15 : 0.0;
    for (int r = 0; r < size.height; ++r) {
      cv::Vec3f* out = img_.ptr<cv::Vec3f>(r);
      const double y = c_.max_y_m - (r + 0.5) * c_.resolution_m;
      for (int col = 0; col < size.width; ++col) {
        const double x = c_.min_x_m + (col + 0.5) * c_.resolution_m;
        const double s = (Eigen::Vector2d(x, y) - f.verge_point).dot(f.verge_normal);
        if (s < 0) continue;
        cv::Vec3f& p = out[col];
        if (s < kerb_m) {
          const float edge = s < 0.02 ? 0.55f : 1.0f;
          for (int k = 0; k < 3; ++k)
            p[k] = kerb[k] * edge * (1.0f + 0.04f * grain.at<float>(r, col));
          continue;
        }
        const float n = fine.at<float>(r, col), m = mid.at<float>(r, col),
                    g = grain.at<float>(r, col);
        if (f.verge_gravel) {
          const float v = 120.0f + 35.0f * g + 20.0f * n;
          p = cv::Vec3f(v * 0.95f, v, v * 1.05f);
        } else {
          const float dryness = std::clamp(0.5f + 0.6f * m, 0.0f, 1.0f);
          const float shade = 1.0f + 0.35f * n + 0.2f * g;
          for (int k = 0; k < 3; ++k)
            p[k] = (grass[k] + (dry[k] - grass[k]) * dryness * 0.6f) * shade;
        }
      }
    }
  }

  // A mask for an irregular blob of the decal's box.
  cv::Mat Blob(const Decal& d, const cv::Rect& roi, double softness_m) {
    cv::Mat mask(roi.size(), CV_8UC1, cv::Scalar(0));
    const cv::Point2f centre(static_cast<float>(c_.PixelOf(d.center).x() - roi.x),
                             static_cast<float>(c_.PixelOf(d.center).y() - roi.y));
    cv::ellipse(mask,
                cv::RotatedRect(centre,
                                cv::Size2f(static_cast<float>(Px(d.length_m)),
                                           static_cast<float>(Px(d.width_m))),
                                static_cast<float>(-RadToDeg(d.yaw_rad))),
                cv::Scalar(255), -1, cv::LINE_AA);
    cv::RNG local(MixSeed(d.seed, 7));
    const cv::Mat noise =
        SmoothNoise(roi.size(), std::max(2.0, Px(std::max(d.width_m, 0.2) / 3)), local);
    cv::Mat m32;
    mask.convertTo(m32, CV_32F, 1.0 / 255);
    m32 = m32.mul(1.0f + 0.8f * noise) - 0.3f;
    const double blur = Px(softness_m);
    if (blur > 0.5) cv::GaussianBlur(m32, m32, cv::Size(), blur);
    m32.convertTo(mask, CV_8UC1, 255.0);
    return mask;
  }

  cv::Rect DecalRoi(const Decal& d, double extra_m) const {
    const double r = std::hypot(d.length_m, d.width_m) / 2 + extra_m;
    return Bounds({c_.PixelOf(d.center + Eigen::Vector2d(-r, -r)),
                   c_.PixelOf(d.center + Eigen::Vector2d(r, r))},
                  2, img_.size());
  }

  void UnderPaint(const Decal& d) {
    const cv::Rect roi = DecalRoi(d, 0.3);
    if (roi.area() <= 0) return;
    cv::Mat mask(roi.size(), CV_8UC1, cv::Scalar(0));
    const float s = static_cast<float>(d.strength);
    switch (d.kind) {
      case DecalKind::kPatch: {
        FillPolygon(BoxPolygon(c_, d.center, d.yaw_rad, d.length_m / 2, d.width_m / 2), roi, &mask);
        const float tone = 1.0f + (Hash01(d.seed, 1, 2) - 0.5f) * 0.3f * s;
        for (int r = 0; r < roi.height; ++r) {
          cv::Vec3f* row = img_.ptr<cv::Vec3f>(roi.y + r) + roi.x;
          const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
          for (int col = 0; col < roi.width; ++col) {
            if (m[col] != 0) row[col] *= 1.0f + (tone - 1.0f) * m[col] / 255.0f;
          }
        }
        break;
      }
      case DecalKind::kDirt:
        Darken(img_, roi, Blob(d, roi, 0.3), 0.25f * s, Colour(1.2f, 0.9f, 0.7f));
        break;
      case DecalKind::kOilStain:
        Darken(img_, roi, Blob(d, roi, 0.05), 0.45f * s);
        break;
      case DecalKind::kPuddle: {
        const cv::Mat m = Blob(d, roi, 0.03);
        Darken(img_, roi, m, 0.45f * s, Colour(0.7f, 1.0f, 1.1f));
        break;
      }
      case DecalKind::kLeaves: {
        cv::RNG local(MixSeed(d.seed, 3));
        const int n = static_cast<int>(40 * d.length_m * d.width_m);
        for (int i = 0; i < n; ++i) {
          const Eigen::Vector2d p =
              d.center + Eigen::Vector2d(local.uniform(-1.0, 1.0) * d.length_m / 2,
                                         local.uniform(-1.0, 1.0) * d.width_m / 2);
          const Eigen::Vector2d px = c_.PixelOf(p);
          const Colour colour =
              local.uniform(0, 2) == 0 ? Colour(30, 80, 120) : Colour(40, 100, 70);
          cv::circle(img_, cv::Point(static_cast<int>(px.x()), static_cast<int>(px.y())),
                     std::max(1, static_cast<int>(Px(0.03))),
                     cv::Scalar(colour[0], colour[1], colour[2]), -1, cv::LINE_AA);
        }
        break;
      }
      case DecalKind::kTyreMark:
        TyreMark(d);
        break;
      case DecalKind::kCrack: {
        cv::RNG local(MixSeed(d.seed, 5));
        Eigen::Vector2d p = d.center;
        double heading = d.yaw_rad;
        std::vector<cv::Point> pts{Fixed(c_.PixelOf(p) - Eigen::Vector2d(roi.x, roi.y))};
        for (double done = 0; done < d.length_m; done += 0.08) {
          heading += local.gaussian(0.4);
          p += Eigen::Vector2d(std::cos(heading), std::sin(heading)) * 0.08;
          pts.push_back(Fixed(c_.PixelOf(p) - Eigen::Vector2d(roi.x, roi.y)));
        }
        cv::polylines(mask, pts, false, cv::Scalar(255), 1, cv::LINE_AA, kShift);
        Darken(img_, roi, mask, 0.5f * s);
        break;
      }
      case DecalKind::kManhole: {
        const Eigen::Vector2d px = c_.PixelOf(d.center) - Eigen::Vector2d(roi.x, roi.y);
        const cv::Point centre = Fixed(px);
        const bool round = Hash01(d.seed, 8, 9) < 0.6;
        const Colour metal = Colour(70, 75, 80) * (0.7f + 0.6f * Hash01(d.seed, 1, 1));
        cv::Mat inner(roi.size(), CV_8UC1, cv::Scalar(0));
        if (round) {
          const int rad = static_cast<int>(Px(d.length_m / 2) * kSubPixel);
          cv::circle(mask, centre, rad, cv::Scalar(255), -1, cv::LINE_AA, kShift);
          cv::circle(inner, centre, static_cast<int>(rad * 0.85), cv::Scalar(255), -1, cv::LINE_AA,
                     kShift);
        } else {
          FillPolygon(BoxPolygon(c_, d.center, d.yaw_rad, d.length_m / 2, d.length_m / 2), roi,
                      &mask);
          FillPolygon(
              BoxPolygon(c_, d.center, d.yaw_rad, d.length_m / 2 - 0.05, d.length_m / 2 - 0.05),
              roi, &inner);
        }
        Blend(img_, roi, mask, metal * 0.8f, 1.0f);
        // A chequered or ribbed cover.
        const double period = Px(0.06 + 0.05 * Hash01(d.seed, 2, 2));
        cv::Mat pattern(roi.size(), CV_8UC1, cv::Scalar(0));
        for (int r = 0; r < roi.height; ++r) {
          for (int col = 0; col < roi.width; ++col) {
            const bool on =
                (static_cast<int>(r / period) + static_cast<int>(col / period)) % 2 == 0;
            pattern.at<std::uint8_t>(r, col) = on ? inner.at<std::uint8_t>(r, col) : 0;
          }
        }
        Blend(img_, roi, inner, metal, 1.0f);
        Darken(img_, roi, pattern, 0.35f);
        break;
      }
      case DecalKind::kGrate: {
        // A drain grate: a frame of cast or galvanised metal around bars a
        // few centimetres apart, or a grid of square holes. The holes are
        // dark but not black (the channel's dirt shows through), so at the
        // top view's 1.7 cm a pixel the cover reads as a grey, finely
        // striped or dotted square, as in real lots, not as a black hole.
        FillPolygon(BoxPolygon(c_, d.center, d.yaw_rad, d.length_m / 2, d.width_m / 2), roi, &mask);
        const float tone = 0.8f + 0.5f * Hash01(d.seed, 1, 3);
        Blend(img_, roi, mask, Colour(125, 130, 135) * tone, 1.0f);
        const double pitch_m = 0.04 + 0.03 * Hash01(d.seed, 2, 3);
        const double hole_m = pitch_m * (0.45 + 0.15 * Hash01(d.seed, 3, 3));
        const double frame_m = 0.03 + 0.03 * Hash01(d.seed, 4, 3);
        const Eigen::Vector2d ax(std::cos(d.yaw_rad), std::sin(d.yaw_rad)), ay(-ax.y(), ax.x());
        const double half_l = d.length_m / 2 - frame_m, half_w = d.width_m / 2 - frame_m;
        if (half_l <= 0 || half_w <= 0) break;
        const auto bars = [&](const Eigen::Vector2d& along, const Eigen::Vector2d& across,
                              double half_along, double half_across) {
          cv::Mat holes(roi.size(), CV_8UC1, cv::Scalar(0));
          for (double t = -half_along + hole_m / 2; t < half_along - hole_m / 2; t += pitch_m) {
            FillPolygon(StrokePolygon(c_, d.center + along * t - across * half_across,
                                      d.center + along * t + across * half_across, hole_m),
                        roi, &holes);
          }
          return holes;
        };
        cv::Mat holes = bars(ax, ay, half_l, half_w);
        if (Hash01(d.seed, 5, 3) < 0.4) cv::bitwise_and(holes, bars(ay, ax, half_w, half_l), holes);
        Darken(img_, roi, holes, 0.35f + 0.25f * Hash01(d.seed, 6, 3));
        break;
      }
      default:
        break;
    }
  }

  // Tyre marks: the arc of a car's turn, one wheel's or both wheels' a
  // track apart. Rubber is laid down unevenly: the mark fades in and out
  // along its length and is darkest in the middle, so it never ends in a
  // crisp crescent.
  void TyreMark(const Decal& d) {
    constexpr double kTrackM = 1.55;
    const bool pair = Hash01(d.seed, 5, 4) < 0.6;
    const cv::Rect roi = DecalRoi(d, 0.3 + (pair ? kTrackM : 0.0));
    if (roi.area() <= 0) return;
    cv::Mat mask(roi.size(), CV_8UC1, cv::Scalar(0));
    const double radius = 3.0 + Hash01(d.seed, 3, 4) * 8.0;
    const Eigen::Vector2d ax(std::cos(d.yaw_rad), std::sin(d.yaw_rad));
    const Eigen::Vector2d centre = d.center + Eigen::Vector2d(-ax.y(), ax.x()) * radius;
    const int thickness = std::max(1, static_cast<int>(std::lround(Px(d.width_m))));
    constexpr int kSteps = 32;
    for (int wheel = 0; wheel < (pair ? 2 : 1); ++wheel) {
      const double r = radius - wheel * kTrackM;
      const float phase = Hash01(d.seed, 6, wheel) * 6.283f;
      cv::Point last;
      for (int i = 0; i <= kSteps; ++i) {
        const double t = static_cast<double>(i) / kSteps;
        const double a = (t - 0.5) * d.length_m / radius;
        const Eigen::Vector2d dir(std::cos(d.yaw_rad - kPi / 2 + a),
                                  std::sin(d.yaw_rad - kPi / 2 + a));
        const cv::Point p = Fixed(c_.PixelOf(centre + dir * r) - Eigen::Vector2d(roi.x, roi.y));
        if (i > 0) {
          // Fades in and out (sine of the arc) and comes and goes along it.
          const double envelope = std::pow(std::sin(kPi * (t - 0.5 / kSteps)), 0.8);
          const double patchy = 0.6 + 0.4 * std::sin(phase + 9.0 * t + 3.0 * std::sin(5.0 * t));
          const int level = static_cast<int>(255 * envelope * patchy);
          cv::line(mask, last, p, cv::Scalar(level), thickness, cv::LINE_AA, kShift);
        }
        last = p;
      }
    }
    cv::GaussianBlur(mask, mask, cv::Size(), std::max(0.8, Px(0.03)));
    Darken(img_, roi, mask, 0.35f * static_cast<float>(d.strength));
  }

  // Decals of paint, below the slot lines.
  void PaintedDecal(const Decal& d) {
    if (d.kind != DecalKind::kArrow && d.kind != DecalKind::kZebra) return;
    const cv::Rect roi = DecalRoi(d, 0.2);
    if (roi.area() <= 0) return;
    cv::Mat mask(roi.size(), CV_8UC1, cv::Scalar(0));
    const Eigen::Vector2d ax(std::cos(d.yaw_rad), std::sin(d.yaw_rad)), ay(-ax.y(), ax.x());
    const PaintKind paint = Hash01(d.seed, 5, 5) < 0.7 ? PaintKind::kWhite : PaintKind::kYellow;
    if (d.kind == DecalKind::kArrow) {
      const double shaft = d.width_m * 0.3, head = d.length_m * 0.35;
      FillPolygon(StrokePolygon(c_, d.center - ax * (d.length_m / 2),
                                d.center + ax * (d.length_m / 2 - head), shaft),
                  roi, &mask);
      FillPolygon({c_.PixelOf(d.center + ax * (d.length_m / 2)),
                   c_.PixelOf(d.center + ax * (d.length_m / 2 - head) + ay * (d.width_m / 2)),
                   c_.PixelOf(d.center + ax * (d.length_m / 2 - head) - ay * (d.width_m / 2))},
                  roi, &mask);
    } else {
      for (double t = -d.length_m / 2; t < d.length_m / 2; t += 0.8) {
        FillPolygon(StrokePolygon(c_, d.center + ax * (t + 0.2) - ay * (d.width_m / 2),
                                  d.center + ax * (t + 0.2) + ay * (d.width_m / 2), 0.4),
                    roi, &mask);
      }
    }
    WornBlend(roi, mask, PaintColour(paint), static_cast<float>(d.strength), 0.2);
  }

  // Decals that stand on the paint: speed bumps and wheel stops.
  void OnTop(const Decal& d) {
    if (d.kind != DecalKind::kSpeedBump && d.kind != DecalKind::kWheelStop) return;
    const cv::Rect roi = DecalRoi(d, 0.3);
    if (roi.area() <= 0) return;
    const Eigen::Vector2d ax(std::cos(d.yaw_rad), std::sin(d.yaw_rad)), ay(-ax.y(), ax.x());
    cv::Mat mask(roi.size(), CV_8UC1, cv::Scalar(0));
    // Its shadow on the floor, then the body.
    FillPolygon(
        BoxPolygon(c_, d.center + ay * (d.width_m * 0.4), d.yaw_rad, d.length_m / 2, d.width_m / 2),
        roi, &mask);
    cv::GaussianBlur(mask, mask, cv::Size(), std::max(0.7, Px(0.03)));
    Darken(img_, roi, mask, 0.5f);
    mask.setTo(0);
    FillPolygon(BoxPolygon(c_, d.center, d.yaw_rad, d.length_m / 2, d.width_m / 2), roi, &mask);
    const bool yellow = Hash01(d.seed, 6, 6) < 0.5 || d.kind == DecalKind::kSpeedBump;
    Blend(img_, roi, mask, yellow ? Colour(30, 170, 215) : Colour(150, 155, 155), 1.0f);
    if (d.kind == DecalKind::kSpeedBump || yellow) {
      cv::Mat stripes(roi.size(), CV_8UC1, cv::Scalar(0));
      for (double t = -d.length_m / 2; t < d.length_m / 2; t += 0.5) {
        FillPolygon(BoxPolygon(c_, d.center + ax * (t + 0.125), d.yaw_rad, 0.125, d.width_m / 2),
                    roi, &stripes);
      }
      cv::bitwise_and(stripes, mask, stripes);
      Blend(img_, roi, stripes, Colour(30, 30, 30), 1.0f);
    }
  }

  // Paint over roi with the scene's wear texture: stronger wear eats more.
  void WornBlend(const cv::Rect& roi, const cv::Mat& mask, const Colour& colour, float opacity,
                 double wear) {
    cv::Mat keep(roi.size(), CV_32F);
    const float w = static_cast<float>(wear);
    for (int r = 0; r < roi.height; ++r) {
      const float* src = wear_.ptr<float>(roi.y + r) + roi.x;
      float* dst = keep.ptr<float>(r);
      for (int col = 0; col < roi.width; ++col) {
        dst[col] = std::clamp((src[col] - w) * 5.0f + 0.5f, 0.0f, 1.0f);
      }
    }
    // Paint is a little dirty: its colour varies with the floor beneath.
    for (int r = 0; r < roi.height; ++r) {
      cv::Vec3f* row = img_.ptr<cv::Vec3f>(roi.y + r) + roi.x;
      const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
      const float* k = keep.ptr<float>(r);
      for (int col = 0; col < roi.width; ++col) {
        if (m[col] == 0) continue;
        const float a = std::clamp(m[col] * (opacity / 255.0f) * k[col], 0.0f, 1.0f);
        cv::Vec3f& p = row[col];
        for (int c = 0; c < 3; ++c) p[c] += (colour[c] * (0.92f + 0.08f * k[col]) - p[c]) * a;
      }
    }
  }

  void StrokeOn(const Stroke& s, cv::Mat* slot_paint) {
    const std::vector<Eigen::Vector2d> poly = StrokePolygon(c_, s.a, s.b, s.width_m);
    const cv::Rect roi = Bounds(poly, 2, img_.size());
    if (roi.area() <= 0) return;
    cv::Mat mask(roi.size(), CV_8UC1, cv::Scalar(0));
    FillPolygon(poly, roi, &mask);
    WornBlend(roi, mask, PaintColour(s.paint), static_cast<float>(s.opacity), s.wear);
    if (slot_paint != nullptr && s.slot_line) {
      cv::Mat target = (*slot_paint)(roi);
      cv::max(target, mask, target);
    }
  }

  void TextOn(const FloorText& t) {
    const double cap_px = Px(t.height_m);
    if (cap_px < 3.0) return;
    cv::Mat glyphs = t.seven_segment ? FontBook::DrawSevenSegment(t.text, cap_px)
                                     : fonts_->Draw(t.text, t.font, cap_px);
    if (t.bold) {
      const int k = std::max(1, static_cast<int>(std::lround(cap_px / 14)));
      cv::dilate(glyphs, glyphs,
                 cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * k + 1, 2 * k + 1)));
    }
    if (t.stencil) {
      // The bridges of a stencil: gaps across the strokes every glyph.
      const int n = std::max(1, static_cast<int>(t.text.size()));
      const double margin = cap_px / 4;
      const double advance = (glyphs.cols - 2 * margin) / n;
      const int gap = std::max(1, static_cast<int>(std::lround(cap_px * 0.08)));
      for (int i = 0; i < n; ++i) {
        const int x = static_cast<int>(margin + advance * (i + 0.5));
        cv::rectangle(glyphs,
                      cv::Rect(x - gap / 2, 0, gap, static_cast<int>(margin + cap_px * 0.3)),
                      cv::Scalar(0), -1);
        cv::rectangle(
            glyphs,
            cv::Rect(x - gap / 2, static_cast<int>(margin + cap_px * 0.7), gap, glyphs.rows),
            cv::Scalar(0), -1);
      }
    }
    // Glyph pixel (gx, gy) -> canvas: centred on t.center, x along right,
    // y down along -up, stretched along the reading direction.
    const Eigen::Vector2d right = t.right.normalized();
    const Eigen::Vector2d up(-right.y(), right.x());
    const Eigen::Vector2d center_px = c_.PixelOf(t.center);
    // Directions on the canvas (y down is -y of the vehicle frame).
    const Eigen::Vector2d r_px(right.x(), -right.y()), d_px(-up.x(), up.y());
    const double sx = t.stretch, sy = 1.0;
    const double gcx = glyphs.cols / 2.0, gcy = glyphs.rows / 2.0;
    cv::Matx23d A(r_px.x() * sx, d_px.x() * sy, 0, r_px.y() * sx, d_px.y() * sy, 0);
    A(0, 2) = center_px.x() - (A(0, 0) * gcx + A(0, 1) * gcy);
    A(1, 2) = center_px.y() - (A(1, 0) * gcx + A(1, 1) * gcy);
    std::vector<Eigen::Vector2d> corners;
    for (const auto& g :
         {Eigen::Vector2d(0, 0), Eigen::Vector2d(glyphs.cols, 0), Eigen::Vector2d(0, glyphs.rows),
          Eigen::Vector2d(glyphs.cols, glyphs.rows)}) {
      corners.emplace_back(A(0, 0) * g.x() + A(0, 1) * g.y() + A(0, 2),
                           A(1, 0) * g.x() + A(1, 1) * g.y() + A(1, 2));
    }
    const cv::Rect roi = Bounds(corners, 2, img_.size());
    if (roi.area() <= 0) return;
    cv::Matx23d local = A;
    local(0, 2) -= roi.x;
    local(1, 2) -= roi.y;
    cv::Mat mask;
    cv::warpAffine(glyphs, mask, local, roi.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    WornBlend(roi, mask, PaintColour(t.paint), static_cast<float>(t.opacity), t.wear);
  }

  // The light (and its tint) times the albedo, into the canvas's 8 bits.
  void LightInto8Bit() {
    const cv::Mat factor = light_.OnCanvas(c_);
    const Colour tint = scene_.light.tint / kRadianceScale;
    for (int r = 0; r < img_.rows; ++r) {
      const cv::Vec3f* row = img_.ptr<cv::Vec3f>(r);
      const float* f = factor.ptr<float>(r);
      cv::Vec3b* out = c_.bgr.ptr<cv::Vec3b>(r);
      for (int col = 0; col < img_.cols; ++col) {
        for (int k = 0; k < 3; ++k)
          out[col][k] = cv::saturate_cast<std::uint8_t>(row[col][k] * f[col] * tint[k]);
      }
    }
  }

  // Hard sun shadows outdoors (solids, the car itself, trees), soft contact
  // shadows under cars indoors.
  void Shadows() {
    const Lighting& l = scene_.light;
    cv::Mat mask(img_.size(), CV_8UC1, cv::Scalar(0));
    const cv::Rect all(0, 0, img_.cols, img_.rows);
    const Eigen::Vector2d away =
        -Eigen::Vector2d(std::cos(l.sun_azimuth_rad), std::sin(l.sun_azimuth_rad));
    const double reach = 1.0 / std::tan(std::max(0.2, l.sun_elevation_rad));
    // corner: the radius of a box's rounded corners (0: sharp).
    const auto cast = [&](const Eigen::Vector2d& c, double yaw, double hx, double hy, double z1,
                          bool round, double corner = 0.0) {
      std::vector<Eigen::Vector2d> foot;
      if (round) {
        for (int i = 0; i < 8; ++i) {
          const double a = i * kPi / 4;
          foot.push_back(c + Eigen::Vector2d(std::cos(a), std::sin(a)) * hx);
        }
      } else {
        const Eigen::Vector2d ax(std::cos(yaw), std::sin(yaw)), ay(-ax.y(), ax.x());
        const double r = std::clamp(corner, 0.0, std::min(hx, hy));
        for (int sx = -1; sx <= 1; sx += 2) {
          for (int sy = -1; sy <= 1; sy += 2) {
            const Eigen::Vector2d inner = c + ax * (sx * (hx - r)) + ay * (sy * (hy - r));
            for (int i = 0; i <= (r > 0 ? 3 : 0); ++i) {
              const double a = i * kPi / 6;  // round the corner in three steps
              foot.push_back(inner + ax * (sx * r * std::cos(a)) + ay * (sy * r * std::sin(a)));
            }
          }
        }
      }
      std::vector<cv::Point2f> pts;
      for (const auto& p : foot) {
        const Eigen::Vector2d a = c_.PixelOf(p), b = c_.PixelOf(p + away * (z1 * reach));
        pts.emplace_back(static_cast<float>(a.x()), static_cast<float>(a.y()));
        pts.emplace_back(static_cast<float>(b.x()), static_cast<float>(b.y()));
      }
      std::vector<cv::Point2f> hull;
      cv::convexHull(pts, hull);
      std::vector<Eigen::Vector2d> poly;
      for (const auto& h : hull) poly.emplace_back(h.x, h.y);
      FillPolygon(poly, all, &mask);
    };
    if (l.outdoor) {
      if (l.shadow_depth <= 0.0) return;
      for (const Solid& s : scene_.solids) {
        if (!s.casts_shadow) continue;
        cast(s.center, s.yaw_rad, s.half_x, s.half_y, s.z1, s.shape != SolidShape::kBox,
             s.corner_radius_m);
      }
      if (options_.ego_shadow) cast(Eigen::Vector2d(1.35, 0), 0.0, 2.35, 0.92, 1.5, false);
      cv::RNG local(MixSeed(l.seed, 0x7ee));
      for (int t = 0; t < l.trees; ++t) {
        const Eigen::Vector2d c(local.uniform(-4.0, 7.0), local.uniform(-6.0, 6.0));
        const double radius = local.uniform(1.5, 3.5);
        const cv::Rect roi = Bounds({c_.PixelOf(c - Eigen::Vector2d(radius, radius)),
                                     c_.PixelOf(c + Eigen::Vector2d(radius, radius))},
                                    2, img_.size());
        if (roi.area() <= 0) continue;
        const cv::Mat leaves = SmoothNoise(roi.size(), Px(0.25), local);
        for (int r = 0; r < roi.height; ++r) {
          for (int col = 0; col < roi.width; ++col) {
            const double dx = (roi.x + col - c_.PixelOf(c).x()) * c_.resolution_m;
            const double dy = (roi.y + r - c_.PixelOf(c).y()) * c_.resolution_m;
            const double fall = 1.0 - std::hypot(dx, dy) / radius;
            if (fall > 0 && leaves.at<float>(r, col) + fall > 0.6)
              mask.at<std::uint8_t>(roi.y + r, roi.x + col) = 255;
          }
        }
      }
      cv::GaussianBlur(mask, mask, cv::Size(), std::max(0.7, Px(0.04)));
      Darken(img_, all, mask, static_cast<float>(l.shadow_depth), Colour(0.85f, 0.95f, 1.0f));
      return;
    }
    // Indoors: the dark under every car (and this one).
    for (const Solid& s : scene_.solids) {
      if (s.material != SolidMaterial::kPaint) continue;
      FillPolygon(BoxPolygon(c_, s.center, s.yaw_rad, s.half_x, s.half_y), all, &mask);
    }
    if (options_.ego_shadow)  // this car
      FillPolygon(BoxPolygon(c_, Eigen::Vector2d(1.35, 0), 0.0, 2.35, 0.92), all, &mask);
    // A wide blur, done at a quarter of the resolution.
    cv::Mat small;
    cv::resize(mask, small, cv::Size(), 0.25, 0.25, cv::INTER_AREA);
    cv::GaussianBlur(small, small, cv::Size(), Px(0.25) / 4);
    cv::resize(small, mask, mask.size(), 0, 0, cv::INTER_LINEAR);
    Darken(img_, all, mask, static_cast<float>(l.shadow_depth) + 0.2f);
  }

  const Scene& scene_;
  const LightMap& light_;
  const FloorPainterOptions& options_;
  FontBook* fonts_;
  Canvas& c_;
  cv::RNG rng_;
  cv::Mat img_;   // CV_32FC3 radiance
  cv::Mat wear_;  // CV_32F in about [0, 1]
};

}  // namespace

Canvas::Canvas(double min_x, double max_y, double width_m, double height_m, double resolution)
    : min_x_m(min_x),
      max_y_m(max_y),
      resolution_m(resolution),
      bgr(static_cast<int>(std::lround(height_m / resolution)),
          static_cast<int>(std::lround(width_m / resolution)), CV_8UC3, cv::Scalar::all(0)) {}

LightMap::LightMap(const Lighting& l) {
  const int n = static_cast<int>(2 * kLightHalfExtentM / kLightGridM);
  grid_ = cv::Mat(n, n, CV_32F);
  min_x_m_ = -kLightHalfExtentM;
  max_y_m_ = kLightHalfExtentM;
  Fill(l);
}

LightMap::LightMap(const Lighting& l, double min_x_m, double min_y_m, double max_x_m,
                   double max_y_m) {
  const int cols = std::max(2, static_cast<int>(std::ceil((max_x_m - min_x_m) / kLightGridM)));
  const int rows = std::max(2, static_cast<int>(std::ceil((max_y_m - min_y_m) / kLightGridM)));
  grid_ = cv::Mat(rows, cols, CV_32F);
  min_x_m_ = min_x_m;
  max_y_m_ = max_y_m;
  Fill(l);
}

LightMap::LightMap(const LightMap& source, double yaw_rad, const Eigen::Vector2d& t) {
  const int n = static_cast<int>(2 * kLightHalfExtentM / kLightGridM);
  grid_ = cv::Mat(n, n, CV_32F);
  min_x_m_ = -kLightHalfExtentM;
  max_y_m_ = kLightHalfExtentM;
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  for (int r = 0; r < n; ++r) {
    const double y = max_y_m_ - (r + 0.5) * kLightGridM;
    for (int col = 0; col < n; ++col) {
      const double x = min_x_m_ + (col + 0.5) * kLightGridM;
      grid_.at<float>(r, col) = source.At(c * x - s * y + t.x(), s * x + c * y + t.y());
    }
  }
}

void LightMap::Fill(const Lighting& l) {
  cv::RNG rng(MixSeed(l.seed, 0x11e));
  const cv::Mat patch = SmoothNoise(grid_.size(), 3.0 / kLightGridM, rng);
  // Night: a few lamps at random grid places.
  std::vector<bool> lit;
  for (int i = 0; i < 64; ++i) lit.push_back(!l.night || rng.uniform(0.0, 1.0) < 0.35);
  const double sigma = 0.35 * l.lamp_spacing_m;
  // The lamp grid's axes (Lighting::lamp_grid_yaw_rad).
  const Eigen::Vector2d gx(std::cos(l.lamp_grid_yaw_rad), std::sin(l.lamp_grid_yaw_rad));
  const Eigen::Vector2d gy(-gx.y(), gx.x());
  for (int r = 0; r < grid_.rows; ++r) {
    const double y = max_y_m_ - (r + 0.5) * kLightGridM;
    for (int c = 0; c < grid_.cols; ++c) {
      const double x = min_x_m_ + (c + 0.5) * kLightGridM;
      double v = 1.0;
      if (!l.outdoor) {
        double pool = 0.0;
        const Eigen::Vector2d rel = Eigen::Vector2d(x, y) - l.lamp_offset;
        const double u = rel.dot(gx), w = rel.dot(gy);
        const double fx = std::round(u / l.lamp_spacing_m);
        const double fy = std::round(w / l.lamp_spacing_m);
        for (int i = -1; i <= 1; ++i) {
          for (int j = -1; j <= 1; ++j) {
            const auto ix = static_cast<std::int64_t>(fx) + i,
                       iy = static_cast<std::int64_t>(fy) + j;
            if (!lit[static_cast<size_t>(((ix * 7 + iy * 13) % 64 + 64) % 64)]) continue;
            // The lamp in the scene's axes (with an unturned grid, to the
            // bit what it always was).
            const Eigen::Vector2d lamp = l.lamp_offset +
                                         gx * (static_cast<double>(ix) * l.lamp_spacing_m) +
                                         gy * (static_cast<double>(iy) * l.lamp_spacing_m);
            const double d2 = (x - lamp.x()) * (x - lamp.x()) + (y - lamp.y()) * (y - lamp.y());
            pool += std::exp(-d2 / (2 * sigma * sigma));
          }
        }
        // The pools' mean over a lamp cell is 2 pi sigma^2 / spacing^2.
        const double mean = 2 * kPi * sigma * sigma / (l.lamp_spacing_m * l.lamp_spacing_m);
        v = l.night ? 0.15 + 1.6 * pool : 1.0 - l.pools + l.pools * pool / mean;
        if (l.backlight > 0) {
          const double s = Eigen::Vector2d(x, y).dot(l.backlight_dir);
          v += l.backlight / (1.0 + std::exp(-(s - 3.0) / 1.5));
        }
      }
      v *= 1.0 + l.patchy * patch.at<float>(r, c);
      grid_.at<float>(r, c) = static_cast<float>(std::max(0.02, v * l.gain));
    }
  }
}

float LightMap::At(double x_m, double y_m) const {
  const double c = (x_m - min_x_m_) / kLightGridM - 0.5;
  const double r = (max_y_m_ - y_m) / kLightGridM - 0.5;
  const double cc = std::clamp(c, 0.0, grid_.cols - 1.001),
               rr = std::clamp(r, 0.0, grid_.rows - 1.001);
  const int ic = static_cast<int>(cc), ir = static_cast<int>(rr);
  const float wc = static_cast<float>(cc - ic), wr = static_cast<float>(rr - ir);
  const float top = grid_.at<float>(ir, ic) * (1 - wc) + grid_.at<float>(ir, ic + 1) * wc;
  const float bottom =
      grid_.at<float>(ir + 1, ic) * (1 - wc) + grid_.at<float>(ir + 1, ic + 1) * wc;
  return top * (1 - wr) + bottom * wr;
}

cv::Mat LightMap::OnCanvas(const Canvas& canvas) const {
  // Canvas pixel (u, v) -> grid (c, r) is affine.
  const double s = canvas.resolution_m / kLightGridM;
  const double c0 = (canvas.min_x_m - min_x_m_) / kLightGridM - 0.5 + 0.5 * s;
  const double r0 = (max_y_m_ - canvas.max_y_m) / kLightGridM - 0.5 + 0.5 * s;
  const cv::Matx23d M(s, 0, c0, 0, s, r0);
  cv::Mat out;
  cv::warpAffine(grid_, out, M, canvas.bgr.size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                 cv::BORDER_REPLICATE);
  return out;
}

void PaintFloor(const Scene& scene, const LightMap& light, const FloorPainterOptions& options,
                FontBook* fonts, Canvas* canvas, cv::Mat* slot_paint) {
  Painter painter(scene, light, options, fonts, canvas);
  painter.Run(slot_paint);
}

namespace {

// Footprints up to this many level-0 texels sample level 0; each further
// level takes footprints twice as large (the near floor of the scene
// renderer: 2 cm texels up to 3.5 cm footprints).
constexpr double kTexelsPerFootprint = 1.75;

}  // namespace

cv::Point2f FloorAtlas::AtlasPixel(const Eigen::Vector2d& p, double footprint_m) const {
  const double ratio = footprint_m / (kTexelsPerFootprint * resolution_m);
  int level = ratio < 1.0 ? 0 : std::ilogb(ratio) + 1;  // floor(log2) + 1
  level = std::clamp(level, 0, static_cast<int>(levels.size()) - 1);
  const double scale = std::ldexp(1.0, level);  // texel edge in level-0 texels
  const double x = (p.x() - min_x_m) / (resolution_m * scale) - 0.5;
  const double y = (max_y_m - p.y()) / (resolution_m * scale) - 0.5;
  const cv::Rect& r = levels[static_cast<size_t>(level)];
  if (!(x > 0.5 && y > 0.5 && x < r.width - 1.5 && y < r.height - 1.5)) return {-10.0f, -10.0f};
  return {static_cast<float>(r.x + x), static_cast<float>(r.y + y)};
}

FloorAtlas PaintFloorAtlas(const Scene& scene, const LightMap& light, FontBook* fonts,
                           double min_x_m, double min_y_m, double max_x_m, double max_y_m,
                           double resolution_m, int levels, double max_pixels) {
  const double width_m = max_x_m - min_x_m, height_m = max_y_m - min_y_m;
  if (!(width_m > 0 && height_m > 0 && resolution_m > 0 && levels >= 1 && levels <= 8)) {
    throw std::invalid_argument("floor atlas: an empty area, a resolution or levels out of range");
  }
  if (width_m * height_m / (resolution_m * resolution_m) > max_pixels) {
    throw std::invalid_argument("floor atlas: " + std::to_string(width_m) + " m x " +
                                std::to_string(height_m) + " m at " + std::to_string(resolution_m) +
                                " m a pixel is over " + std::to_string(max_pixels) + " pixels");
  }
  Canvas canvas(min_x_m, max_y_m, width_m, height_m, resolution_m);
  FloorPainterOptions options;
  options.ego_shadow = false;
  PaintFloor(scene, light, options, fonts, &canvas);
  std::vector<cv::Mat> chain = {canvas.bgr};
  for (int k = 1; k < levels; ++k) {
    cv::Mat next;
    cv::pyrDown(chain.back(), next);
    chain.push_back(next);
  }
  FloorAtlas atlas;
  atlas.min_x_m = min_x_m;
  atlas.max_y_m = max_y_m;
  atlas.resolution_m = resolution_m;
  const int gap = 4;
  int right_height = 0, right_width = 0;
  for (int k = 1; k < levels; ++k) {
    right_height += chain[static_cast<size_t>(k)].rows + gap;
    right_width = std::max(right_width, chain[static_cast<size_t>(k)].cols);
  }
  atlas.bgr =
      cv::Mat(std::max(canvas.bgr.rows, right_height),
              canvas.bgr.cols + (levels > 1 ? gap + right_width : 0), CV_8UC3, cv::Scalar::all(0));
  int y = 0;
  for (int k = 0; k < levels; ++k) {
    const cv::Mat& level = chain[static_cast<size_t>(k)];
    const cv::Rect where = k == 0 ? cv::Rect(0, 0, level.cols, level.rows)
                                  : cv::Rect(canvas.bgr.cols + gap, y, level.cols, level.rows);
    if (k > 0) y += level.rows + gap;
    level.copyTo(atlas.bgr(where));
    atlas.levels.push_back(where);
  }
  return atlas;
}

}  // namespace parkslam::scene
