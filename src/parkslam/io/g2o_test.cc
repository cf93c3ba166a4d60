#include "parkslam/io/g2o.h"

#include <gtest/gtest.h>

#include <string>

#include "parkslam/io/io_error.h"

namespace parkslam::io {
namespace {

// The message of the IoError that parsing `text` throws, or "" if none.
std::string ParseError(const std::string& text) {
  try {
    ParseG2o(text, "g.g2o");
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

constexpr const char* kSmall =
    "# a small graph\n"
    "EDGE_SE2 0 1 1 0 0.1 500 0 0 500 0 1000\n"  // edges may come before vertices
    "VERTEX_SE2 0 0 0 0\n"
    "VERTEX_SE2 1 1.01 0.02 0.09\n"
    "VERTEX_SE2 2 2 0.1 0.2\n"
    "VERTEX_XY 10 3 4\n"
    "EDGE_SE2 1 2 1 0 0.1 500 1 0 400 0 1000\n"
    "EDGE_SE2 0 2 2 0.1 0.2 100 0 0 100 0 200\n"
    "EDGE_SE2_XY 2 10 1 3.9 50 0 50\n"
    "FIX 0\n";

TEST(G2oTest, ParsesEveryElement) {
  const graph::PoseGraph g = ParseG2o(kSmall, "g.g2o");
  ASSERT_EQ(g.poses.size(), 3u);
  EXPECT_DOUBLE_EQ(g.poses.at(1).x(), 1.01);
  EXPECT_DOUBLE_EQ(g.poses.at(1).yaw(), 0.09);
  ASSERT_EQ(g.points.size(), 1u);
  EXPECT_DOUBLE_EQ(g.points.at(10).y(), 4.0);
  ASSERT_EQ(g.pose_edges.size(), 3u);
  EXPECT_EQ(g.pose_edges[1].from, 1);
  EXPECT_DOUBLE_EQ(g.pose_edges[1].information(0, 1), 1.0);
  EXPECT_DOUBLE_EQ(g.pose_edges[1].information(1, 0), 1.0);
  EXPECT_DOUBLE_EQ(g.pose_edges[1].information(1, 1), 400.0);
  EXPECT_FALSE(graph::IsOdometry(g.pose_edges[2]));
  ASSERT_EQ(g.point_edges.size(), 1u);
  EXPECT_DOUBLE_EQ(g.point_edges[0].p_pose.y(), 3.9);
  EXPECT_EQ(g.fixed, std::set<int>{0});
}

TEST(G2oTest, RoundTripsExactly) {
  graph::PoseGraph g = ParseG2o(kSmall, "g.g2o");
  g.poses[1] = SE2(1.0 / 3.0, -2.0 / 7.0, 0.123456789012345);
  const std::string text = FormatG2o(g);
  const graph::PoseGraph back = ParseG2o(text, "back.g2o");
  EXPECT_EQ(FormatG2o(back), text);
  EXPECT_EQ(back.poses.at(1).x(), 1.0 / 3.0);
  EXPECT_EQ(back.poses.at(1).yaw(), g.poses.at(1).yaw());
}

TEST(G2oTest, ErrorsNameTheLineAndTheField) {
  EXPECT_EQ(ParseError("VERTEX_SE2 0 0 0\n"),
            "g.g2o:1: VERTEX_SE2: expected 4 values after the type, found 3");
  EXPECT_EQ(ParseError("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 nan 0\n"),
            "g.g2o:2: VERTEX_SE2.y: not a finite number");
  EXPECT_EQ(ParseError("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1e300 0 0\n"),
            "g.g2o:2: VERTEX_SE2.x: 1e+300 is beyond the plausible 100000 m");
  EXPECT_EQ(ParseError("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 0 1 0 0\n"),
            "g.g2o:2: VERTEX_SE2.id: vertex 0 is already defined on line 1");
  EXPECT_EQ(ParseError("VERTEX_SE2 -3 0 0 0\n"),
            "g.g2o:1: VERTEX_SE2.id: not a vertex id (an integer in [0, 2^31)) '-3'");
  EXPECT_EQ(ParseError("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 0 0\n"
                       "EDGE_SE2 0 1 1 0 0 1 0 0 -1 0 1\n"),
            "g.g2o:3: EDGE_SE2.I: the information matrix is not positive definite");
  EXPECT_EQ(ParseError("VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 5 1 0 0 1 0 0 1 0 1\n"),
            "g.g2o:2: EDGE_SE2.to: no VERTEX_SE2 5");
  EXPECT_EQ(ParseError("VERTEX_SE2 0 0 0 0\nEDGE_SE2_XY 0 1 1 0 1 0 1\n"),
            "g.g2o:2: EDGE_SE2_XY.point: no VERTEX_XY 1");
  EXPECT_EQ(ParseError("VERTEX_SE2 0 0 0 0\nFIX 3\n"), "g.g2o:2: FIX.id: no vertex 3");
  EXPECT_EQ(ParseError("VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n"),
            "g.g2o:1: VERTEX_SE3:QUAT: unknown element type (this reader takes VERTEX_SE2, "
            "VERTEX_XY, EDGE_SE2, EDGE_SE2_MIXTURE, EDGE_SE2_XY and FIX)");
  EXPECT_EQ(ParseError("# nothing\n"), "g.g2o: no VERTEX_SE2");
}

constexpr const char* kVertices =
    "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0\nVERTEX_SE2 3 3 0 0\n";

TEST(G2oTest, ReadsAMixtureOfAClosureAndItsNull) {
  const graph::PoseGraph g =
      ParseG2o(std::string(kVertices) +
                   "EDGE_SE2_MIXTURE 0 3 2 EDGE_SE2 1 0 3 3 0.1 0.2 44.72 0 0 44.72 0 44.72 "
                   "EDGE_SE2 0.01 0 3 3 0.1 0.2 4.472e-10 0 0 4.472e-10 0 4.472e-10\n"
                   // the null first, its weight and scale the same
                   "EDGE_SE2_MIXTURE 1 3 2 EDGE_SE2 0.02 1 3 2 0 0 2e-9 0 0 2e-9 0 2e-9 "
                   "EDGE_SE2 2 1 3 2 0 0 200 0 0 200 0 200\n",
               "m.g2o");
  ASSERT_EQ(g.pose_edges.size(), 2u);
  EXPECT_EQ(g.pose_edges[0].to, 3);
  EXPECT_DOUBLE_EQ(g.pose_edges[0].T_from_to.y(), 0.1);
  EXPECT_DOUBLE_EQ(g.pose_edges[0].information(1, 1), 44.72);
  EXPECT_DOUBLE_EQ(g.pose_edges[1].information(2, 2), 200.0);
  ASSERT_TRUE(g.file_null.has_value());
  EXPECT_DOUBLE_EQ(g.file_null->weight, 0.01);
  EXPECT_NEAR(g.file_null->information_scale, 1e-11, 1e-20);
  EXPECT_FALSE(ParseG2o(kSmall, "g.g2o").file_null.has_value());
}

TEST(G2oTest, MixturesOtherThanAClosureAndItsNullAreRefused) {
  const std::string v = kVertices;
  EXPECT_EQ(ParseError(v + "EDGE_SE2_MIXTURE 0 3 2 EDGE_SE2 1 0 3 3 0 0 1 0 0 1 0 1 "
                           "EDGE_SE2 0.01 0 2 3 0 0 1e-6 0 0 1e-6 0 1e-6\n"),
            "g.g2o:5: EDGE_SE2_MIXTURE.component: both components must join vertices 0 and 3");
  EXPECT_EQ(ParseError(v + "EDGE_SE2_MIXTURE 0 3 2 EDGE_SE2 1 0 3 3 0 0 1 0 0 1 0 1 "
                           "EDGE_SE2 0.01 0 3 2 0 0 1e-6 0 0 1e-6 0 1e-6\n"),
            "g.g2o:5: EDGE_SE2_MIXTURE.component: the two components measure different poses "
            "(this reader takes a closure and its null hypothesis)");
  EXPECT_EQ(ParseError(v + "EDGE_SE2_MIXTURE 0 3 2 EDGE_SE2 1 0 3 3 0 0 1 0 0 1 0 1 "
                           "EDGE_SE2 0.01 0 3 3 0 0 1e-6 0 0 2e-6 0 1e-6\n"),
            "g.g2o:5: EDGE_SE2_MIXTURE.I: the null's information is not a scale below 1 of the "
            "closure's");
  EXPECT_EQ(ParseError(v + "EDGE_SE2_MIXTURE 0 3 2 EDGE_SE2 1 0 3 3 0 0 1 0 0 1 0 1 "
                           "EDGE_SE2 0.01 0 3 3 0 0 1e-6 0 0 1e-6 0 1e-6\n"
                           "EDGE_SE2_MIXTURE 1 3 2 EDGE_SE2 1 1 3 2 0 0 1 0 0 1 0 1 "
                           "EDGE_SE2 0.1 1 3 2 0 0 1e-6 0 0 1e-6 0 1e-6\n"),
            "g.g2o:6: EDGE_SE2_MIXTURE.component: a null hypothesis other than line 5's (this "
            "reader takes one per file)");
  EXPECT_EQ(ParseError(v + "EDGE_SE2_MIXTURE 0 3 3 EDGE_SE2 1 0 3 3 0 0 1 0 0 1 0 1 "
                           "EDGE_SE2 0.01 0 3 3 0 0 1e-6 0 0 1e-6 0 1e-6\n"),
            "g.g2o:5: EDGE_SE2_MIXTURE.components: this reader takes two components (a closure "
            "and its null), found '3'");
}

}  // namespace
}  // namespace parkslam::io
