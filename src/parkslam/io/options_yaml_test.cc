#include "parkslam/io/options_yaml.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "parkslam/io/io_error.h"

namespace parkslam::io {
namespace {

using ::testing::HasSubstr;

std::string OptionsErrorOf(const std::string& yaml) {
  try {
    OptionsFromYaml(yaml, AlgorithmOptions{}, "o.yaml");
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

TEST(OptionsYamlTest, TheShippedExampleLoadsAndChangesWhatItSays) {
  const AlgorithmOptions o =
      LoadOptionsFile(std::filesystem::path(PARKSLAM_CONFIG_DIR) / "options.yaml");
  EXPECT_EQ(o.front_end.detector, perception::DetectorKind::kLearned);
  EXPECT_EQ(o.front_end.corner_sigma_m, 0.05);
  EXPECT_EQ(o.mapper.min_observations, 4);
  EXPECT_EQ(o.localizer.lost_position_sigma_m, 1.0);
  EXPECT_EQ(o.follower.max_decel_mps2, 0.6);
  // Everything else keeps its default.
  const AlgorithmOptions defaults;
  EXPECT_EQ(o.mapper.null_weight, defaults.mapper.null_weight);
  EXPECT_EQ(o.front_end.slots.min_contrast_grey, defaults.front_end.slots.min_contrast_grey);
}

TEST(OptionsYamlTest, DumpedDefaultsReadBackExactly) {
  AlgorithmOptions changed;
  changed.mapper.null_chi2 = 31.25;
  changed.front_end.top_view.camera_priority_rad = {0.1, -0.2, 0.3, 0.4};
  changed.front_end.top_view.seam_style = camera::SeamStyle::kFootprintRays;
  changed.front_end.tags.quad_decimate = 1.5f;
  changed.localizer.reloc_min_inliers = 9;
  changed.front_end.detector = perception::DetectorKind::kClassical;
  const std::string text = OptionsToYaml(changed);
  const AlgorithmOptions back = OptionsFromYaml(text, AlgorithmOptions{}, "dump.yaml");
  EXPECT_EQ(OptionsToYaml(back), text);
  EXPECT_EQ(back.mapper.null_chi2, 31.25);
  EXPECT_EQ(back.front_end.top_view.camera_priority_rad.size(), 4u);
  EXPECT_EQ(back.front_end.tags.quad_decimate, 1.5f);
  EXPECT_EQ(back.localizer.reloc_min_inliers, 9);
  EXPECT_THAT(text, HasSubstr("\nmapper:\n  keyframe_distance_m: 0.1\n"));
  EXPECT_THAT(text, HasSubstr("\n  detector: classical\n"));
  EXPECT_EQ(back.front_end.detector, perception::DetectorKind::kClassical);
  EXPECT_THAT(text, HasSubstr("\n    seam_style: footprint_rays\n"));
  EXPECT_EQ(back.front_end.top_view.seam_style, camera::SeamStyle::kFootprintRays);
  // The default is the learned front end, and a file may choose either.
  EXPECT_THAT(OptionsToYaml(AlgorithmOptions{}), HasSubstr("\n  detector: learned\n"));
  EXPECT_EQ(OptionsFromYaml("front_end:\n  detector: classical\n", AlgorithmOptions{}, "d.yaml")
                .front_end.detector,
            perception::DetectorKind::kClassical);
}

TEST(OptionsYamlTest, UnknownKeysAndBadValuesNameTheFileLineAndKey) {
  EXPECT_EQ(OptionsErrorOf("mapper:\n  null_wieght: 0.1\n"),
            "o.yaml:2: mapper.null_wieght: unknown key (did you mean 'null_weight'?)");
  EXPECT_EQ(OptionsErrorOf("mappr:\n  null_weight: 0.1\n"),
            "o.yaml:1: mappr: unknown key (did you mean 'mapper'?)");
  EXPECT_EQ(OptionsErrorOf("front_end:\n  slots:\n    min_contrast_grey: abc\n"),
            "o.yaml:3: front_end.slots.min_contrast_grey: expected a number, got 'abc'");
  EXPECT_EQ(OptionsErrorOf("mapper:\n  null_weight: -1\n"),
            "o.yaml:2: mapper.null_weight: -1 is outside the plausible range (0, 1]");
  EXPECT_EQ(OptionsErrorOf("follower:\n  max_decel_mps2: 0\n"),
            "o.yaml:2: follower.max_decel_mps2: 0 is outside the plausible range (0, 10] m/s^2");
  // A relation between two keys: the line of the one the message names.
  EXPECT_EQ(OptionsErrorOf("front_end:\n  tag_max_height_m: 0.5\n"),
            "o.yaml:2: front_end.tag_max_height_m: must be in [1, 10] m");
  // The example: a tag size of 1e308 mapped no tag, exit 0.
  EXPECT_EQ(OptionsErrorOf("front_end:\n  tags: {quad_decimate: 2,\n    tag_size_m: 1e308}\n"),
            "o.yaml:3: front_end.tags.tag_size_m: 1e+308 is outside the plausible range (0, 5] m");
  // A default made wrong by another key has no line of its own.
  EXPECT_EQ(OptionsErrorOf("front_end:\n  tag_min_height_m: 2\n"),
            "o.yaml: front_end.tag_max_height_m: must be in [2, 10] m");
  EXPECT_EQ(OptionsErrorOf("front_end:\n  detector: lernd\n"),
            "o.yaml:2: front_end.detector: 'lernd' is none of classical, learned");
  EXPECT_THAT(OptionsErrorOf("front_end:\n  detector: [learned]\n"),
              HasSubstr("o.yaml:2: front_end.detector: "));
  EXPECT_EQ(OptionsErrorOf(""), "");
}

}  // namespace
}  // namespace parkslam::io
