#include "parkslam/io/rig_yaml.h"

#include <gtest/gtest.h>

#include "parkslam/io/io_error.h"

namespace parkslam::io {
namespace {

TEST(RigYamlTest, DefaultRigRoundTrips) {
  const camera::CameraRig rig = camera::DefaultRig();
  const camera::CameraRig back = RigFromYaml(RigToYaml(rig), "rig.yaml");
  ASSERT_EQ(back.cameras.size(), rig.cameras.size());
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    EXPECT_EQ(back.cameras[i].name, rig.cameras[i].name);
    EXPECT_EQ(back.cameras[i].intrinsics.kind, rig.cameras[i].intrinsics.kind);
    EXPECT_NEAR(back.cameras[i].intrinsics.distortion[1], rig.cameras[i].intrinsics.distortion[1],
                1e-15);
    EXPECT_TRUE(back.cameras[i].T_vehicle_camera.matrix().isApprox(
        rig.cameras[i].T_vehicle_camera.matrix(), 1e-12))
        << rig.cameras[i].name;
  }
}

std::string RigErrorOf(const std::string& yaml) {
  try {
    RigFromYaml(yaml, "rig.yaml");
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

TEST(RigYamlTest, UnknownKeyNamesItsPath) {
  std::string yaml = RigToYaml(camera::DefaultRig());
  yaml.replace(yaml.find("    fy:"), 7, "    fz:");
  EXPECT_NE(RigErrorOf(yaml).find("cameras[0]"), std::string::npos) << RigErrorOf(yaml);
}

TEST(RigYamlTest, BadModelAndSizeAreRejected) {
  std::string yaml = RigToYaml(camera::DefaultRig());
  std::string bad_model = yaml;
  bad_model.replace(bad_model.find("fisheye"), 7, "fishbowl");
  EXPECT_NE(RigErrorOf(bad_model).find("cameras[0].model"), std::string::npos);
  std::string bad_size = yaml;
  bad_size.replace(bad_size.find("width: 640"), 10, "width: -5");
  EXPECT_NE(RigErrorOf(bad_size).find("cameras[0].width"), std::string::npos);
  EXPECT_NE(RigErrorOf("cameras: [").find("rig.yaml"), std::string::npos);
}

// The default rig's YAML with the first `from` replaced by `to`.
std::string DefaultRigWith(const std::string& from, const std::string& to) {
  std::string yaml = RigToYaml(camera::DefaultRig());
  const std::size_t at = yaml.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) yaml.replace(at, from.size(), to);
  return yaml;
}

// Values beyond the limits of common/plausible_ranges.h, named by file,
// line and field. The first camera is the front fisheye (640 x 480, f =
// 180 px, at (3.7, 0, 0.6) m).
TEST(RigYamlTest, ImplausibleValuesAreRejectedNamingLineAndField) {
  EXPECT_EQ(RigErrorOf(DefaultRigWith("fx: 180", "fx: 1e308")),
            "rig.yaml:7: cameras[0].fx: 1e+308 is outside the plausible range [1, 100000] px");
  EXPECT_EQ(RigErrorOf(DefaultRigWith("fy: 180", "fy: 0")),
            "rig.yaml:8: cameras[0].fy: 0 is outside the plausible range [1, 100000] px");
  EXPECT_EQ(RigErrorOf(DefaultRigWith("cx: 319.5", "cx: 1000")),
            "rig.yaml:9: cameras[0].cx: 1000 is outside the plausible range [-320, 960] px");
  EXPECT_EQ(RigErrorOf(DefaultRigWith("cy: 239.5", "cy: -300")),
            "rig.yaml:10: cameras[0].cy: -300 is outside the plausible range [-240, 720] px");
  EXPECT_EQ(RigErrorOf(DefaultRigWith("width: 640", "width: 20000")),
            "rig.yaml:5: cameras[0].width: 20000 is outside the plausible range [16, 16384] px");
  EXPECT_EQ(
      RigErrorOf(DefaultRigWith("width: 640\n    height: 480", "width: 16000\n    height: 16000")),
      "rig.yaml:6: cameras[0].height: 16000 x 16000 is 256000000 pixels, beyond the "
      "plausible 64000000");
  EXPECT_EQ(RigErrorOf(DefaultRigWith("distortion: [0.02,", "distortion: [1e5,")),
            "rig.yaml:11: cameras[0].distortion[0]: 1e+05 is beyond the plausible 100");
  EXPECT_EQ(RigErrorOf(DefaultRigWith("position_m: [3.7000000000000002, 0, 0.59999999999999998]",
                                      "position_m: [3.7, 0, -0.2]")),
            "rig.yaml:12: cameras[0].position_m[2]: -0.2 puts the camera on or under the ground "
            "(z is up)");
  EXPECT_EQ(RigErrorOf(DefaultRigWith("position_m: [3.7000000000000002, 0, 0.59999999999999998]",
                                      "position_m: [3.7, 0, 6]")),
            "rig.yaml:12: cameras[0].position_m[2]: 6 is beyond the plausible 5 m");
  EXPECT_EQ(RigErrorOf(DefaultRigWith("position_m: [3.7000000000000002,", "position_m: [-25,")),
            "rig.yaml:12: cameras[0].position_m[0]: -25 is beyond the plausible 20 m");
  EXPECT_EQ(RigErrorOf(DefaultRigWith("roll_deg: ", "roll_deg: 1e9 #")),
            "rig.yaml:15: cameras[0].roll_deg: 1e+09 is beyond the plausible 360 deg");
}

}  // namespace
}  // namespace parkslam::io
