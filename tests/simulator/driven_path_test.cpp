#include "simulator/driven_path.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace statebench::sim {
namespace {

TEST(DrivenPath, ConcatenatesLanesWithoutRepeatingJoints) {
  DrivenPath path;
  path.AppendLane("a", {Vec3(0, 0, 0), Vec3(10, 0, 0)}, 10.0);
  // A junction lane starting where "a" ends, with a custom SUMO length of 4 m for its 5 m shape.
  path.AppendLane(":j", {Vec3(10, 0, 0), Vec3(13, 4, 0)}, 4.0);
  // The next lane repeats the joint and has a duplicated vertex of its own.
  path.AppendLane("b", {Vec3(13, 4, 0), Vec3(13, 4, 0), Vec3(13, 14, 0)}, 10.0);
  ASSERT_EQ(path.points().size(), 4u);
  EXPECT_EQ(path.arc_lengths(), (std::vector<double>{0.0, 10.0, 15.0, 25.0}));
  ASSERT_EQ(path.lanes().size(), 3u);
  EXPECT_DOUBLE_EQ(path.lanes()[1].s_begin_m, 10.0);
  EXPECT_DOUBLE_EQ(path.lanes()[1].s_end_m, 15.0);
  EXPECT_DOUBLE_EQ(path.lanes()[2].s_begin_m, 15.0);
  EXPECT_DOUBLE_EQ(path.length_m(), 25.0);
}

TEST(DrivenPath, LanePositionsScaleByShapeOverLaneLength) {
  DrivenPath path;
  path.AppendLane("a", {Vec3(0, 0, 0), Vec3(10, 0, 0)}, 10.0);
  path.AppendLane(":j", {Vec3(10, 0, 0), Vec3(13, 4, 0)}, 4.0);
  const DrivenLane& j = path.lanes()[1];
  EXPECT_DOUBLE_EQ(j.ArcLength(0.0), 10.0);
  EXPECT_DOUBLE_EQ(j.ArcLength(2.0), 12.5);  // half of the 4 m lane: half of the 5 m shape
  EXPECT_DOUBLE_EQ(j.ArcLength(4.0), 15.0);
  EXPECT_TRUE(path.PointAt(j.ArcLength(2.0)).isApprox(Vec3(11.5, 2.0, 0.0)));
}

TEST(DrivenPath, ArcLengthIsThreeDimensional) {
  DrivenPath path;
  path.AppendLane("ramp", {Vec3(0, 0, 0), Vec3(30, 0, 40), Vec3(60, 0, 0)}, 100.0);
  EXPECT_DOUBLE_EQ(path.length_m(), 100.0);  // two 3-4-5 segments of 50 m
  EXPECT_TRUE(path.PointAt(25.0).isApprox(Vec3(15, 0, 20)));
  EXPECT_TRUE(path.PointAt(-1.0).isApprox(Vec3(0, 0, 0)));
  EXPECT_TRUE(path.PointAt(1e3).isApprox(Vec3(60, 0, 0)));
}

TEST(DrivenPath, KeepsAGapBetweenLanesThatDoNotTouch) {
  DrivenPath path;
  path.AppendLane("a", {Vec3(0, 0, 0), Vec3(10, 0, 0)}, 10.0);
  path.AppendLane("b", {Vec3(10, 3, 0), Vec3(20, 3, 0)}, 10.0);
  EXPECT_DOUBLE_EQ(path.lanes()[1].s_begin_m, 13.0);
  EXPECT_DOUBLE_EQ(path.length_m(), 23.0);
}

TEST(DrivenPath, RejectsDegenerateLanes) {
  DrivenPath path;
  EXPECT_THROW(path.AppendLane("x", {Vec3(0, 0, 0)}, 1.0), std::invalid_argument);
  EXPECT_THROW(path.AppendLane("x", {Vec3(0, 0, 0), Vec3(1, 0, 0)}, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace statebench::sim
