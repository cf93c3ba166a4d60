#include "parkslam/live/frame_set_assembler.h"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <vector>

namespace parkslam::live {
namespace {

constexpr TimeNs kMs = 1'000'000;

// A 1 x 1 image whose one pixel tells which it was.
ImagePlane Marked(std::uint8_t value) {
  return {1, 1, std::make_shared<const std::vector<std::uint8_t>>(1, value)};
}

std::uint8_t MarkOf(const ImagePlane& image) { return (*image.pixels)[0]; }

TEST(FrameSetAssemblerTest, GivesEachSetAtItsLastImage) {
  FrameSetAssembler sets({"front", "left", "rear"}, 20 * kMs);
  EXPECT_TRUE(sets.Add("left", 1000 * kMs, Marked(2)).empty());
  EXPECT_TRUE(sets.Add("front", 1002 * kMs, Marked(1)).empty());
  const std::vector<CameraFrame> out = sets.Add("rear", 995 * kMs, Marked(3));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].t_ns, 1002 * kMs);  // the reference camera's time
  EXPECT_EQ(out[0].cameras, (std::vector<std::string>{"front", "left", "rear"}));
  ASSERT_EQ(out[0].images.size(), 3u);
  EXPECT_EQ(MarkOf(out[0].images[0]), 1);
  EXPECT_EQ(MarkOf(out[0].images[1]), 2);
  EXPECT_EQ(MarkOf(out[0].images[2]), 3);
  EXPECT_EQ(sets.stats().sets, 1);
  EXPECT_EQ(sets.stats().images_unmatched, 0);
}

TEST(FrameSetAssemblerTest, TakesTheNearestImageWithinTheSkew) {
  FrameSetAssembler sets({"front", "left"}, 20 * kMs);
  sets.Add("left", 970 * kMs, Marked(7));  // too early for 1000
  sets.Add("left", 985 * kMs, Marked(8));  // within, not the nearest
  sets.Add("left", 998 * kMs, Marked(9));  // the nearest
  const std::vector<CameraFrame> out = sets.Add("front", 1000 * kMs, Marked(1));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(MarkOf(out[0].images[1]), 9);
  EXPECT_EQ(sets.stats().images_unmatched, 2);  // 970 and 985 went into no set
}

TEST(FrameSetAssemblerTest, DropsAReferenceImageThatCanNoLongerBeCompleted) {
  FrameSetAssembler sets({"front", "left"}, 20 * kMs);
  EXPECT_TRUE(sets.Add("front", 1000 * kMs, Marked(1)).empty());
  EXPECT_TRUE(sets.Add("front", 1200 * kMs, Marked(2)).empty());
  // The left camera missed 1000: its next image is past it beyond the skew,
  // and makes the set of 1200.
  const std::vector<CameraFrame> out = sets.Add("left", 1195 * kMs, Marked(3));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].t_ns, 1200 * kMs);
  EXPECT_EQ(MarkOf(out[0].images[0]), 2);
  EXPECT_EQ(sets.stats().images_unmatched, 1);
}

TEST(FrameSetAssemblerTest, RefusesImagesOutOfOrderAndCapsTheWait) {
  FrameSetAssembler sets({"front", "left"}, 20 * kMs, /*buffer=*/2);
  sets.Add("front", 1000 * kMs, Marked(1));
  EXPECT_TRUE(sets.Add("front", 900 * kMs, Marked(2)).empty());
  EXPECT_TRUE(sets.Add("front", 1000 * kMs, Marked(3)).empty());  // a duplicate
  EXPECT_EQ(sets.stats().images_out_of_order, 2);
  // A camera that never comes: the reference images wait, two at most.
  sets.Add("front", 1200 * kMs, Marked(4));
  sets.Add("front", 1400 * kMs, Marked(5));
  EXPECT_EQ(sets.stats().images_unmatched, 1);
  const std::vector<CameraFrame> out = sets.Add("left", 1405 * kMs, Marked(6));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(MarkOf(out[0].images[0]), 5);
  EXPECT_EQ(sets.stats().images_unmatched, 2);  // 1000 dropped for the cap, 1200 unmatched
  EXPECT_EQ(sets.stats().sets, 1);
}

TEST(FrameSetAssemblerTest, ForgetsOtherImagesNoReferenceCanTake) {
  FrameSetAssembler sets({"front", "left"}, 20 * kMs);
  sets.Add("front", 1000 * kMs, Marked(1));
  ASSERT_EQ(sets.Add("left", 1001 * kMs, Marked(2)).size(), 1u);
  sets.Add("left", 1003 * kMs, Marked(3));  // the next front image is after 1000 + 20
  sets.Add("front", 1200 * kMs, Marked(4));
  EXPECT_EQ(sets.stats().images_unmatched, 1);
  const std::vector<CameraFrame> out = sets.Add("left", 1210 * kMs, Marked(5));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(MarkOf(out[0].images[1]), 5);
}

TEST(FrameSetAssemblerTest, RefusesBadArguments) {
  EXPECT_THROW(FrameSetAssembler({}, kMs), std::invalid_argument);
  EXPECT_THROW(FrameSetAssembler({"front", "front"}, kMs), std::invalid_argument);
  EXPECT_THROW(FrameSetAssembler({"front"}, -1), std::invalid_argument);
  EXPECT_THROW(FrameSetAssembler({"front"}, kMs, 0), std::invalid_argument);
  FrameSetAssembler sets({"front"}, kMs);
  EXPECT_THROW(sets.Add("rear", 0, Marked(1)), std::invalid_argument);
  // One camera alone: every image is a set.
  EXPECT_EQ(sets.Add("front", 0, Marked(1)).size(), 1u);
}

}  // namespace
}  // namespace parkslam::live
