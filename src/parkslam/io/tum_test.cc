#include "parkslam/io/tum.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "parkslam/common/angles.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/test_util.h"

namespace parkslam::io {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;

Trajectory SampleTrajectory() {
  return {{0, SE2(0.0, 0.0, 0.0)},
          {1, SE2(1.25, -2.5, kPi)},  // 1 ns later; yaw exactly pi
          {1'000'000'001, SE2(12.345678, 9.87654, -kPi + 1e-6)},
          {123'456'789'012'345, SE2(-80.5, 50.25, 1.2345678901)},
          {123'456'789'012'346, SE2(1e3, -1e3, -0.5 * kPi)}};
}

TEST(TumTest, RoundTripKeepsTimesExactAndYawTo1e9) {
  const Trajectory original = SampleTrajectory();
  const Trajectory read = ParseTum(FormatTum(original), "mem.tum");
  ASSERT_EQ(read.size(), original.size());
  for (std::size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read[i].t_ns, original[i].t_ns);
    EXPECT_NEAR(read[i].T_map_vehicle.x(), original[i].T_map_vehicle.x(), 5e-7);
    EXPECT_NEAR(read[i].T_map_vehicle.y(), original[i].T_map_vehicle.y(), 5e-7);
    EXPECT_NEAR(AngleDiff(read[i].T_map_vehicle.yaw(), original[i].T_map_vehicle.yaw()), 0.0, 1e-9);
  }
}

TEST(TumTest, RoundTripThroughAFile) {
  const TempDir dir;
  const Trajectory original = SampleTrajectory();
  WriteTum(dir / "sub/traj.tum", original);
  const Trajectory read = ReadTum(dir / "sub/traj.tum");
  ASSERT_EQ(read.size(), original.size());
  EXPECT_EQ(read.back().t_ns, 123'456'789'012'346);
  EXPECT_NEAR(read.back().T_map_vehicle.yaw(), -0.5 * kPi, 1e-9);
}

TEST(TumTest, FormatsOnePoseAsTumLine) {
  const Trajectory trajectory = {{1'500'000'000, SE2(1.0, -2.0, 0.5 * kPi)}};
  EXPECT_EQ(FormatTum(trajectory),
            "# t x y z qx qy qz qw\n"
            "1.500000000 1.000000 -2.000000 0 0 0 0.7071067812 0.7071067812\n");
}

TEST(TumTest, FormatsNegativeTimesExactly) {
  const Trajectory trajectory = {{-1'500'000'001, SE2()}};
  EXPECT_THAT(FormatTum(trajectory), HasSubstr("\n-1.500000001 "));
  EXPECT_EQ(ParseTum(FormatTum(trajectory), "m").front().t_ns, -1'500'000'001);
}

TEST(TumTest, SkipsCommentsAndBlankLinesAndAcceptsTabs) {
  const Trajectory read =
      ParseTum("# header\n\n0.1 1 2 0 0 0 0 1\r\n  # indented comment\n0.2\t3\t4\t0\t0\t0\t0\t1\n",
               "mem.tum");
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].t_ns, 100'000'000);
  EXPECT_EQ(read[1].t_ns, 200'000'000);
  EXPECT_DOUBLE_EQ(read[1].T_map_vehicle.x(), 3.0);
  EXPECT_DOUBLE_EQ(read[1].T_map_vehicle.y(), 4.0);
}

TEST(TumTest, RoundsTimeToTheNearestNanosecond) {
  const Trajectory read = ParseTum("1.0000000015 0 0 0 0 0 0 1\n2.5e0 0 0 0 0 0 0 1\n", "m");
  EXPECT_EQ(read[0].t_ns, 1'000'000'002);
  EXPECT_EQ(read[1].t_ns, 2'500'000'000);
}

TEST(TumTest, ReadsHeadingOfAnUnnormalizedQuaternion) {
  // 2 * (0, 0, sin 0.5, cos 0.5): a rotation of 1 rad about z.
  const Trajectory read = ParseTum("0 0 0 0 0 0 0.958851077208406 1.755165123780746\n", "m");
  EXPECT_NEAR(read[0].T_map_vehicle.yaw(), 1.0, 1e-12);
}

TEST(TumTest, ReadsHeadingOfATiltedRotation) {
  // Yaw 0.3 then roll 0.2 (z-y-x Euler): qw, qx, qy, qz of that rotation.
  const double cy = std::cos(0.15), sy = std::sin(0.15);
  const double cr = std::cos(0.1), sr = std::sin(0.1);
  const double qw = cy * cr, qx = cy * sr, qy = sy * sr, qz = sy * cr;
  const std::string line = "0 0 0 0 " + std::to_string(qx) + " " + std::to_string(qy) + " " +
                           std::to_string(qz) + " " + std::to_string(qw) + "\n";
  EXPECT_NEAR(ParseTum(line, "m")[0].T_map_vehicle.yaw(), 0.3, 1e-5);
}

TEST(TumTest, RejectsWrongColumnCountNamingTheLine) {
  const std::string error =
      ErrorOf([] { ParseTum("# c\n0 0 0 0 0 0 0 1\n1 0 0 0 0 1\n", "t.tum"); });
  EXPECT_THAT(error, HasSubstr("t.tum:3:"));
  EXPECT_THAT(error, HasSubstr("expected 8 columns"));
  EXPECT_THAT(error, HasSubstr("got 6"));
}

TEST(TumTest, RejectsANonNumberNamingTheField) {
  EXPECT_EQ(ErrorOf([] { ParseTum("0 0 abc 0 0 0 0 1\n", "t.tum"); }),
            "t.tum:1: y: not a number 'abc'");
}

TEST(TumTest, RejectsNaNAndInfinity) {
  EXPECT_EQ(ErrorOf([] { ParseTum("0 nan 0 0 0 0 0 1\n", "t.tum"); }),
            "t.tum:1: x: not a finite number");
  EXPECT_EQ(ErrorOf([] { ParseTum("inf 0 0 0 0 0 0 1\n", "t.tum"); }),
            "t.tum:1: t: not a finite number");
}

// Positions beyond kMaxCoordinate_m (common/plausible_ranges.h); z is
// dropped, but held to the same bound.
TEST(TumTest, RejectsImplausiblePositionsNamingLineAndField) {
  EXPECT_EQ(ErrorOf([] { ParseTum("0 0 0 0 0 0 0 1\n1 1e308 0 0 0 0 0 1\n", "t.tum"); }),
            "t.tum:2: x: 1e+308 is beyond the plausible 100000 m");
  EXPECT_EQ(ErrorOf([] { ParseTum("# t x y z qx qy qz qw\n0 5 -100000.5 0 0 0 0 1\n", "t.tum"); }),
            "t.tum:2: y: -100000.5 is beyond the plausible 100000 m");
  EXPECT_EQ(ErrorOf([] { ParseTum("0 -100000 100000 1e300 0 0 0 1\n", "t.tum"); }),
            "t.tum:1: z: 1e+300 is beyond the plausible 100000 m");
  EXPECT_EQ(ErrorOf([] { ParseTum("0 -100000 100000 -99999 0 0 0 1\n", "t.tum"); }), "");
}

TEST(TumTest, RejectsTimestampsThatDoNotIncrease) {
  const std::string error =
      ErrorOf([] { ParseTum("1.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n", "t.tum"); });
  EXPECT_THAT(error, HasSubstr("t.tum:2: t: not strictly increasing"));
}

TEST(TumTest, RejectsAZeroQuaternion) {
  EXPECT_THAT(ErrorOf([] { ParseTum("0 0 0 0 0 0 0 0\n", "t.tum"); }), HasSubstr("t.tum:1:"));
}

TEST(TumTest, RejectsAFileWithoutPoses) {
  EXPECT_EQ(ErrorOf([] { ParseTum("# only a comment\n\n", "t.tum"); }), "t.tum: no poses");
  EXPECT_EQ(ErrorOf([] { ParseTum("", "t.tum"); }), "t.tum: no poses");
}

TEST(TumTest, ReadingAMissingFileNamesIt) {
  const TempDir dir;
  EXPECT_THAT(ErrorOf([&] { ReadTum(dir / "missing.tum"); }), HasSubstr("missing.tum"));
}

TEST(TumTest, WritingRefusesANonFinitePose) {
  const TempDir dir;
  const Trajectory bad = {{0, SE2(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0)}};
  EXPECT_THAT(ErrorOf([&] { WriteTum(dir / "bad.tum", bad); }), HasSubstr("not a finite pose"));
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.tum"));
}

}  // namespace
}  // namespace parkslam::io
