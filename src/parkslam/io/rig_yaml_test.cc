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
    EXPECT_NEAR(back.cameras[i].intrinsics.distortion[1], rig.cameras[i].intrinsics.distortion[1], 1e-15);
    EXPECT_TRUE(back.cameras[i].T_vehicle_camera.matrix().isApprox(
        rig.cameras[i].T_vehicle_camera.matrix(), 1e-12))
        << rig.cameras[i].name;
  }
}

std::string ErrorOf(const std::string& yaml) {
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
  EXPECT_NE(ErrorOf(yaml).find("cameras[0]"), std::string::npos) << ErrorOf(yaml);
}

TEST(RigYamlTest, BadModelAndSizeAreRejected) {
  std::string yaml = RigToYaml(camera::DefaultRig());
  std::string bad_model = yaml;
  bad_model.replace(bad_model.find("fisheye"), 7, "fishbowl");
  EXPECT_NE(ErrorOf(bad_model).find("cameras[0].model"), std::string::npos);
  std::string bad_size = yaml;
  bad_size.replace(bad_size.find("width: 640"), 10, "width: -5");
  EXPECT_NE(ErrorOf(bad_size).find("cameras[0].width"), std::string::npos);
  EXPECT_NE(ErrorOf("cameras: [").find("rig.yaml"), std::string::npos);
}

}  // namespace
}  // namespace parkslam::io
