// SUMO's run as the lidar world's input: lanes, junctions, traffic frames, and the pitch
// convention (SUMO: R = Rz(yaw) Ry(pitch), nose-up negative; lidar: nose-up positive).
#include "simulator/world_from_sumo.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "sensors/traffic_window.hpp"

namespace statebench::sim {
namespace {

TrafficBox NoseUpCar() {
  TrafficBox b;
  b.id = "car";
  b.p_world_center = Vec3(0.0, 0.0, 1.0);
  b.yaw_rad = 0.3;
  b.pitch_rad = -0.2;  // SUMO convention: climbing
  b.length_m = 4.0;
  b.width_m = 1.8;
  b.height_m = 1.0;
  return b;
}

// Where a vertical ray from above hits the top face, computed with SUMO's own rotation.
double TopFaceRangeSumo(const TrafficBox& b, const Vec3& origin) {
  const Mat3 R =
      (Eigen::AngleAxisd(b.yaw_rad, Vec3::UnitZ()) * Eigen::AngleAxisd(b.pitch_rad, Vec3::UnitY()))
          .toRotationMatrix();
  const Vec3 n = R * Vec3::UnitZ();
  const Vec3 q = b.p_world_center + R * Vec3(0.0, 0.0, 0.5 * b.height_m);
  const Vec3 d = -Vec3::UnitZ();
  return (q - origin).dot(n) / d.dot(n);
}

TEST(WorldFromSumo, TrafficBoxPitchKeepsTheOrientation) {
  const TrafficBox sumo_box = NoseUpCar();
  const sensors::TrafficBox lidar_box = ToLidarTrafficBox(sumo_box);
  EXPECT_EQ(lidar_box.pitch_rad, 0.2);
  EXPECT_EQ(lidar_box.yaw_rad, 0.3);
  EXPECT_EQ(lidar_box.centre_world, sumo_box.p_world_center);
  // Rays down onto the front and the rear half of the roof: the front is higher when climbing.
  const Vec3 forward(std::cos(0.3), std::sin(0.3), 0.0);
  for (const double s : {-1.5, -0.5, 0.5, 1.5}) {
    const Vec3 origin = sumo_box.p_world_center + s * forward + Vec3(0.0, 0.0, 10.0);
    const auto hit = sensors::IntersectTrafficBox(lidar_box, origin, -Vec3::UnitZ(), 50.0);
    ASSERT_TRUE(hit.has_value()) << s;
    EXPECT_NEAR(hit->range_m, TopFaceRangeSumo(sumo_box, origin), 1e-9) << s;
  }
  const auto front = sensors::IntersectTrafficBox(
      lidar_box, sumo_box.p_world_center + 1.5 * forward + Vec3(0, 0, 10), -Vec3::UnitZ(), 50.0);
  EXPECT_LT(front->range_m, 10.0 - 0.5 - 0.25);  // raised by about 1.5 tan(0.2) = 0.30 m
}

TEST(WorldFromSumo, LanesJunctionsAndTrafficFrames) {
  SumoResult sumo;
  sumo.lanes.push_back({"a_0", "a", false, 3.2, 100.0, {Vec3(0, 0, 1), Vec3(100, 0, 2)}});
  sumo.lanes.push_back({":j_0", ":j", true, 3.0, 10.0, {Vec3(100, 0, 2), Vec3(105, 5, 2)}});
  sumo.lanes.push_back({"degenerate", "d", false, 3.0, 0.0, {Vec3(0, 0, 0)}});
  sumo.junctions.push_back({"j", {Vec3(98, -3, 2), Vec3(108, -3, 2), Vec3(108, 7, 2)}});
  const sensors::RoadGeometry roads = ToRoadGeometry(sumo);
  ASSERT_EQ(roads.lanes.size(), 2u);  // the one-point lane has no corridor
  EXPECT_EQ(roads.lanes[0].width_m, 3.2);
  EXPECT_EQ(roads.lanes[1].centre.back(), Vec3(105, 5, 2));
  ASSERT_EQ(roads.junctions.size(), 1u);

  TrafficFrame f0{0.0, {NoseUpCar()}};
  TrafficFrame f1{0.1, {NoseUpCar()}};
  f1.boxes[0].p_world_center.x() += 1.0;
  sumo.traffic = {f0, f1};
  const sensors::TrafficTimeline timeline = ToTrafficTimeline(sumo);
  ASSERT_EQ(timeline.frames().size(), 2u);
  EXPECT_EQ(timeline.frames()[1].t_ns, 100 * kNsPerMillisecond);
  const auto mid = timeline.BoxesAt(50 * kNsPerMillisecond);
  ASSERT_EQ(mid.size(), 1u);
  EXPECT_NEAR(mid[0].centre_world.x(), 0.5, 1e-12);
  EXPECT_EQ(mid[0].pitch_rad, 0.2);

  sumo.traffic[1].t_s = 0.0;  // not increasing
  EXPECT_THROW(ToTrafficTimeline(sumo), InputError);
}

}  // namespace
}  // namespace statebench::sim
