#include "parkslam/render/renderer.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <stdexcept>

#include "parkslam/common/angles.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/world.h"

namespace parkslam::render {
namespace {

const sim::World& RendererWorld() {
  static const sim::World world = [] {
    const sim::ScenarioConfig scenario = sim::DefaultScenario();
    return sim::BuildWorld(scenario.world);
  }();
  return world;
}

const camera::CameraRig& Rig() {
  static const camera::CameraRig rig = camera::DefaultRig();
  return rig;
}

const Renderer& DefaultRenderer() {
  static const Renderer renderer(RendererWorld(), Rig(), RenderOptions{}, 1);
  return renderer;
}

// The default renderer without sensor noise.
const Renderer& CleanRenderer() {
  static const Renderer renderer = [] {
    RenderOptions options;
    options.noise_sigma = 0.0;
    return Renderer(RendererWorld(), Rig(), options, 1);
  }();
  return renderer;
}

const camera::CameraConfig& CameraNamed(const std::string& name) {
  const camera::CameraConfig* config = Rig().Find(name);
  if (config == nullptr) throw std::invalid_argument("no camera " + name);
  return *config;
}

// The pixel of a map point in a camera of the rig, the vehicle at T_map_vehicle.
std::optional<Eigen::Vector2d> ProjectMapPoint(const camera::CameraConfig& config,
                                               const SE2& T_map_vehicle,
                                               const Eigen::Vector3d& p_map) {
  const Eigen::Isometry3d T_map_camera = VehiclePose3d(T_map_vehicle) * config.T_vehicle_camera;
  return camera::CameraModel(config.intrinsics).Project(T_map_camera.inverse() * p_map);
}

// The vehicle pose that puts `config`'s centre at c_map (on the ground
// plane) with its optical axis pointing at yaw_rad in the map.
SE2 VehiclePoseForCamera(const camera::CameraConfig& config, const Eigen::Vector2d& c_map,
                         double yaw_rad) {
  const Eigen::Vector3d forward = config.T_vehicle_camera.linear() * Eigen::Vector3d::UnitZ();
  const double vehicle_yaw = yaw_rad - std::atan2(forward.y(), forward.x());
  const SE2 rotation(0.0, 0.0, vehicle_yaw);
  return SE2(c_map - rotation * Eigen::Vector2d(config.T_vehicle_camera.translation().head<2>()),
             vehicle_yaw);
}

double Mean(const cv::Mat& image) { return cv::mean(image)[0]; }

TEST(RendererTest, SameInputsGiveTheSameBytes) {
  const SE2 pose(20.0, 9.1, 0.1);
  const TimeNs t_ns = 1'234'567'890;
  std::vector<std::string> names;
  for (const camera::CameraConfig& c : Rig().cameras) names.push_back(c.name);
  const std::vector<cv::Mat> first = DefaultRenderer().RenderAll(pose, t_ns, names);
  const std::vector<cv::Mat> again = DefaultRenderer().RenderAll(pose, t_ns, names);
  const Renderer other(RendererWorld(), Rig(), RenderOptions{}, 1);
  const std::vector<cv::Mat> rebuilt = other.RenderAll(pose, t_ns, names);
  ASSERT_EQ(first.size(), names.size());
  for (size_t i = 0; i < names.size(); ++i) {
    const camera::CameraIntrinsics& in = CameraNamed(names[i]).intrinsics;
    ASSERT_EQ(first[i].type(), CV_8UC1);
    ASSERT_EQ(first[i].cols, in.width);
    ASSERT_EQ(first[i].rows, in.height);
    EXPECT_EQ(cv::norm(first[i], again[i], cv::NORM_INF), 0.0) << names[i];
    EXPECT_EQ(cv::norm(first[i], rebuilt[i], cv::NORM_INF), 0.0) << names[i];
  }
}

TEST(RendererTest, NoiseIsNewInEveryFrame) {
  const SE2 pose(20.0, 9.1, 0.1);
  const cv::Mat a = DefaultRenderer().Render("front_mono", pose, 0);
  const cv::Mat b = DefaultRenderer().Render("front_mono", pose, 100'000'000);
  EXPECT_GT(cv::norm(a, b, cv::NORM_L1), 0.5 * static_cast<double>(a.total()));
}

// The front fisheye looks north into row B from aisle 1; slot 26's right
// separating line runs north from (13.0, 12.6).
TEST(RendererTest, SlotLineAppearsWhereTheCameraModelProjectsIt) {
  const sim::WorldSlot* slot = nullptr;
  for (const sim::WorldSlot& s : RendererWorld().slots) {
    if (s.painted_id == "26") slot = &s;
  }
  ASSERT_NE(slot, nullptr);
  const Eigen::Vector2d entrance = slot->corners_map[1];
  const Eigen::Vector2d side = (slot->corners_map[2] - entrance).normalized();
  const Eigen::Vector2d across = (slot->corners_map[1] - slot->corners_map[0]).normalized();
  const SE2 pose(entrance.x() - 1.0, entrance.y() - 4.5, kPi / 2);
  const camera::CameraConfig& front = CameraNamed("front");
  const cv::Mat image = DefaultRenderer().Render("front", pose, 0);
  int checked = 0;
  for (double depth_m : {1.5, 2.5, 3.5}) {
    const Eigen::Vector2d on_line = entrance + depth_m * side;
    const Eigen::Vector2d beside = on_line + 0.3 * across;
    const auto line_px = ProjectMapPoint(front, pose, {on_line.x(), on_line.y(), 0.0});
    const auto beside_px = ProjectMapPoint(front, pose, {beside.x(), beside.y(), 0.0});
    ASSERT_TRUE(line_px && beside_px) << depth_m;
    const int line_value = image.at<std::uint8_t>(static_cast<int>(std::lround(line_px->y())),
                                                  static_cast<int>(std::lround(line_px->x())));
    const int beside_value = image.at<std::uint8_t>(static_cast<int>(std::lround(beside_px->y())),
                                                    static_cast<int>(std::lround(beside_px->x())));
    EXPECT_GT(line_value, 150) << "depth " << depth_m << " at " << line_px->transpose();
    EXPECT_LT(beside_value, 120) << "depth " << depth_m << " at " << beside_px->transpose();
    EXPECT_GT(line_value - beside_value, 60) << depth_m;
    ++checked;
  }
  EXPECT_EQ(checked, 3);
}

struct Detection {
  int id;
  Eigen::Vector2d center_px;  // camera-model convention
  std::array<Eigen::Vector2d, 4> corners_px;
};

// libapriltag on a CV_8UC1 image; its pixel centres sit at half-integers,
// so 0.5 is subtracted to return to the camera models' convention.
std::vector<Detection> DetectTags(const cv::Mat& image) {
  apriltag_family_t* family = tag36h11_create();
  apriltag_detector_t* detector = apriltag_detector_create();
  apriltag_detector_add_family(detector, family);
  detector->nthreads = 1;
  detector->quad_decimate = 1.0f;
  image_u8_t im{image.cols, image.rows, static_cast<int32_t>(image.step[0]), image.data};
  zarray_t* detections = apriltag_detector_detect(detector, &im);
  std::vector<Detection> out;
  for (int i = 0; i < zarray_size(detections); ++i) {
    apriltag_detection_t* det = nullptr;
    zarray_get(detections, i, &det);
    Detection d{det->id, {det->c[0] - 0.5, det->c[1] - 0.5}, {}};
    for (int k = 0; k < 4; ++k) d.corners_px[k] = {det->p[k][0] - 0.5, det->p[k][1] - 0.5};
    out.push_back(d);
  }
  apriltag_detections_destroy(detections);
  apriltag_detector_destroy(detector);
  tag36h11_destroy(family);
  return out;
}

// A free view of a tag from straight in front of it: the first tag in the
// hall whose line of sight at `distance_m` is clear.
struct TagView {
  const sim::WorldTag* tag = nullptr;
  SE2 T_map_vehicle;
};

TagView FindTagView(const camera::CameraConfig& camera, double distance_m, double offset_m) {
  const sim::World& world = RendererWorld();
  for (const sim::WorldTag& tag : world.tags) {
    const Eigen::Vector2d n(std::cos(tag.normal_yaw_rad), std::sin(tag.normal_yaw_rad));
    const Eigen::Vector2d right(-n.y(), n.x());
    const Eigen::Vector2d c_map = tag.p_map + distance_m * n + offset_m * right;
    sim::RegionConfig inner = world.hall;
    inner.min_x_m += 5.0;
    inner.min_y_m += 5.0;
    inner.max_x_m -= 5.0;
    inner.max_y_m -= 5.0;
    if (!inner.Contains(c_map)) continue;
    const int skip_wall = tag.on_pillar ? -1 : tag.mount_index;
    const int skip_pillar = tag.on_pillar ? tag.mount_index : -1;
    if (sim::SegmentBlocked(world, c_map, tag.p_map + 0.01 * n, skip_wall, skip_pillar)) continue;
    const double yaw = std::atan2(tag.p_map.y() - c_map.y(), tag.p_map.x() - c_map.x());
    return {&tag, VehiclePoseForCamera(camera, c_map, yaw + 0.15)};
  }
  return {};
}

TEST(RendererTest, TagsDecodeWithTheirIdsWhereTheyProject) {
  const camera::CameraConfig& mono = CameraNamed("front_mono");
  const RenderOptions& options = DefaultRenderer().options();
  std::map<int, const sim::WorldTag*> tags_by_id;
  for (const sim::WorldTag& t : RendererWorld().tags) tags_by_id[t.tag_id] = &t;
  for (double distance_m : {3.0, 7.0, 12.0}) {
    const TagView view = FindTagView(mono, distance_m, 0.8);
    ASSERT_NE(view.tag, nullptr) << distance_m;
    const cv::Mat image = DefaultRenderer().Render("front_mono", view.T_map_vehicle, 0);
    const std::vector<Detection> detections = DetectTags(image);
    bool found = false;
    for (const Detection& d : detections) {
      ASSERT_TRUE(tags_by_id.count(d.id)) << "decoded an ID the world lacks: " << d.id;
      const auto expected =
          ProjectMapPoint(mono, view.T_map_vehicle, TagCenter3d(*tags_by_id[d.id], options));
      ASSERT_TRUE(expected.has_value()) << d.id;
      EXPECT_LT((d.center_px - *expected).norm(), 2.0)
          << "tag " << d.id << " at " << distance_m << " m: " << d.center_px.transpose() << " vs "
          << expected->transpose();
      found |= d.id == view.tag->tag_id;
    }
    EXPECT_TRUE(found) << "tag " << view.tag->tag_id << " at " << distance_m << " m";
  }
}

TEST(RendererTest, PnpOnDetectedCornersGivesTheTagDistanceWithinFivePercent) {
  const camera::CameraConfig& mono = CameraNamed("front_mono");
  const camera::CameraIntrinsics& in = mono.intrinsics;
  const cv::Matx33d K(in.fx, 0, in.cx, 0, in.fy, in.cy, 0, 0, 1);
  const cv::Vec4d distortion(in.distortion[0], in.distortion[1], in.distortion[2],
                             in.distortion[3]);
  for (double distance_m : {3.0, 7.0, 12.0}) {
    const TagView view = FindTagView(mono, distance_m, 0.8);
    ASSERT_NE(view.tag, nullptr);
    const cv::Mat image = DefaultRenderer().Render("front_mono", view.T_map_vehicle, 0);
    const std::vector<Detection> detections = DetectTags(image);
    const Detection* target = nullptr;
    for (const Detection& d : detections) {
      if (d.id == view.tag->tag_id) target = &d;
    }
    ASSERT_NE(target, nullptr) << distance_m;
    const double s = view.tag->size_m / 2;
    const std::vector<cv::Point3d> object = {{-s, s, 0}, {s, s, 0}, {s, -s, 0}, {-s, -s, 0}};
    std::vector<cv::Point2d> corners;
    for (const Eigen::Vector2d& p : target->corners_px) corners.emplace_back(p.x(), p.y());
    cv::Vec3d rvec, tvec;
    ASSERT_TRUE(
        cv::solvePnP(object, corners, K, distortion, rvec, tvec, false, cv::SOLVEPNP_IPPE_SQUARE));
    const Eigen::Isometry3d T_map_camera =
        VehiclePose3d(view.T_map_vehicle) * mono.T_vehicle_camera;
    const double truth_m =
        (TagCenter3d(*view.tag, DefaultRenderer().options()) - T_map_camera.translation()).norm();
    EXPECT_NEAR(cv::norm(tvec), truth_m, 0.05 * truth_m) << "at " << distance_m << " m";
  }
}

TEST(RendererTest, BrightnessScalesTheMeanIntensity) {
  const SE2 pose(20.0, 9.1, 0.1);
  RenderOptions dim;
  dim.brightness = 0.6;
  const Renderer dim_renderer(RendererWorld(), Rig(), dim, 1);
  const double bright_mean = Mean(DefaultRenderer().Render("front_mono", pose, 0));
  const double dim_mean = Mean(dim_renderer.Render("front_mono", pose, 0));
  EXPECT_GT(bright_mean, 30.0);
  EXPECT_NEAR(dim_mean / bright_mean, 0.6, 0.05);
}

TEST(RendererTest, NoiseSigmaSetsThePixelVariance) {
  const SE2 pose(20.0, 9.1, 0.1);
  const double sigma = DefaultRenderer().options().noise_sigma;
  ASSERT_EQ(sigma, 3.0);
  const cv::Mat clean = CleanRenderer().Render("front_mono", pose, 0);
  const cv::Mat noisy = DefaultRenderer().Render("front_mono", pose, 0);
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (int r = 0; r < clean.rows; ++r) {
    for (int c = 0; c < clean.cols; ++c) {
      const int clean_value = clean.at<std::uint8_t>(r, c);
      if (clean_value < 15 || clean_value > 240) continue;  // away from clipping
      const double d = noisy.at<std::uint8_t>(r, c) - clean_value;
      sum += d;
      sum2 += d * d;
      ++n;
    }
  }
  ASSERT_GT(n, 100000);
  const double mean = sum / n;
  EXPECT_NEAR(mean, 0.0, 0.05);
  // Rounding to whole grey levels adds 1/12.
  EXPECT_NEAR(sum2 / n - mean * mean, sigma * sigma + 1.0 / 12, 0.05 * sigma * sigma);
}

TEST(RendererTest, BlurSmoothsTheImage) {
  const SE2 pose(20.0, 9.1, 0.1);
  RenderOptions blurred;
  blurred.noise_sigma = 0.0;
  blurred.blur_sigma_px = 2.0;
  const auto gradient_energy = [](const cv::Mat& image) {
    cv::Mat dx;
    cv::Sobel(image, dx, CV_32F, 1, 0);
    return cv::norm(dx, cv::NORM_L2SQR);
  };
  const cv::Mat a = CleanRenderer().Render("front", pose, 0);
  const cv::Mat b = Renderer(RendererWorld(), Rig(), blurred, 1).Render("front", pose, 0);
  EXPECT_LT(gradient_energy(b), 0.5 * gradient_energy(a));
}

TEST(RendererTest, ParkedCarOccludesTheFloorOfItsSlot) {
  RenderOptions options;
  options.parked_cars = 1;
  options.noise_sigma = 0.0;
  const Renderer with_car(RendererWorld(), Rig(), options, 1);
  const Renderer& without = CleanRenderer();
  ASSERT_EQ(with_car.parked_cars().size(), 1u);
  const ParkedCar& car = with_car.parked_cars().front();
  // The front camera 6 m from the car's centre, looking at it.
  const camera::CameraConfig& mono = CameraNamed("front_mono");
  const sim::WorldSlot& slot = RendererWorld().slots[static_cast<size_t>(car.slot_index)];
  const Eigen::Vector2d out_of_slot =
      ((slot.corners_map[0] + slot.corners_map[1]) / 2 - car.center_map).normalized();
  const Eigen::Vector2d c_map = car.center_map + 7.0 * out_of_slot;
  const SE2 pose =
      VehiclePoseForCamera(mono, c_map, std::atan2(-out_of_slot.y(), -out_of_slot.x()));
  const auto px = ProjectMapPoint(mono, pose, {car.center_map.x(), car.center_map.y(), 0.7});
  ASSERT_TRUE(px.has_value());
  const cv::Rect patch(static_cast<int>(px->x()) - 10, static_cast<int>(px->y()) - 10, 21, 21);
  const cv::Mat a = with_car.Render("front_mono", pose, 0);
  const cv::Mat b = without.Render("front_mono", pose, 0);
  EXPECT_GT(cv::norm(a(patch), b(patch), cv::NORM_L1) / patch.area(), 10.0);
}

TEST(RendererTest, UnknownCameraThrows) {
  EXPECT_THROW(DefaultRenderer().Render("roof", SE2(), 0), std::invalid_argument);
}

TEST(RendererTest, RejectsInvalidOptions) {
  RenderOptions options;
  options.noise_sigma = -1.0;
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("noise_sigma"), std::string::npos);
  EXPECT_THROW(Renderer(RendererWorld(), Rig(), options, 1), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::render
