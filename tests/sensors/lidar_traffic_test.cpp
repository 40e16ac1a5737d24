#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "lidar_test_fixtures.hpp"
#include "sensors/lidar_simulator.hpp"
#include "sensors/synthetic_roads.hpp"
#include "sensors/traffic_timeline.hpp"
#include "sensors/traffic_window.hpp"

namespace statebench::sensors {
namespace {

TrafficBox Car(const std::string& id, double x, double y, double yaw = 0.0) {
  TrafficBox b;
  b.id = id;
  b.centre_world = Vec3(x, y, 0.75);
  b.yaw_rad = yaw;
  return b;
}

// Position of a point relative to a box: max over axes of |p_box| - half extent (<= 0 inside,
// ~0 on the surface).
double BoxDistance(const TrafficBox& box, const Vec3& p_world) {
  const Mat3 r = (Eigen::AngleAxisd(box.yaw_rad, Vec3::UnitZ()) *
                  Eigen::AngleAxisd(-box.pitch_rad, Vec3::UnitY()))
                     .toRotationMatrix();
  const Vec3 p = r.transpose() * (p_world - box.centre_world);
  const Vec3 half(0.5 * box.length_m, 0.5 * box.width_m, 0.5 * box.height_m);
  return (p.cwiseAbs() - half).maxCoeff();
}

TEST(TrafficTimeline, InterpolatesBetweenStepsAndAppliesPresenceRule) {
  const TrafficTimeline timeline({
      {0, {Car("a", 0.0, 0.0, 3.0), Car("b", 5.0, 5.0)}},
      {100'000'000, {Car("a", 1.0, 2.0, -3.0), Car("c", 9.0, 9.0)}},
  });
  const std::vector<TrafficBox> mid = timeline.BoxesAt(25'000'000);
  ASSERT_EQ(mid.size(), 2u);  // a interpolated, b held until the midpoint; c not yet there
  EXPECT_EQ(mid[0].id, "a");
  EXPECT_NEAR(mid[0].centre_world.x(), 0.25, 1e-12);
  EXPECT_NEAR(mid[0].centre_world.y(), 0.5, 1e-12);
  // Yaw goes the short way through pi: 3.0 -> -3.0 is +0.283 rad.
  const double short_arc = 2.0 * M_PI - 6.0;
  EXPECT_NEAR(std::remainder(mid[0].yaw_rad - (3.0 + 0.25 * short_arc), 2.0 * M_PI), 0.0, 1e-12);
  EXPECT_EQ(mid[1].id, "b");

  const std::vector<TrafficBox> late = timeline.BoxesAt(75'000'000);
  ASSERT_EQ(late.size(), 2u);
  EXPECT_EQ(late[0].id, "a");
  EXPECT_EQ(late[1].id, "c");
  EXPECT_EQ(timeline.BoxesAt(500'000'000).size(), 2u);  // last frame held

  EXPECT_THROW(TrafficTimeline({{10, {}}, {10, {}}}), InputError);
  EXPECT_THROW(TrafficTimeline({{0, {Car("a", 0, 0), Car("a", 1, 1)}}}), InputError);
}

TEST(TrafficWindow, ExactBoxIntersection) {
  const TrafficBox box = Car("a", 10.0, 0.0, M_PI / 2);  // length along y: x faces at 10 +- 0.9
  const auto hit = IntersectTrafficBox(box, Vec3(0.0, 0.0, 0.75), Vec3::UnitX(), 100.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 9.1, 1e-12);
  EXPECT_NEAR(hit->normal_world.x(), -1.0, 1e-12);
  EXPECT_FALSE(IntersectTrafficBox(box, Vec3(0.0, 0.0, 0.75), Vec3::UnitX(), 9.0));
  EXPECT_FALSE(IntersectTrafficBox(box, Vec3(0.0, 0.0, 1.6), Vec3::UnitX(), 100.0));    // above
  EXPECT_FALSE(IntersectTrafficBox(box, Vec3(10.0, 0.0, 0.75), Vec3::UnitX(), 100.0));  // inside
}

struct TrafficCounts {
  int on_passing = 0;
  int on_leaving = 0;
  int at_old_place = 0;         // non-ground points inside where "passing" was at t = 0
  int ground_at_old_place = 0;  // ground points under where "passing" was at t = 0
};

// Checks that every non-ground point lies on a vehicle surface at its own firing time, and counts.
TrafficCounts ScanTraffic(const LidarWorld& world, const SE3& pose, TimeNs t0) {
  const LidarSimulator sim(world, testing::ExactLidar("hesai_xt32"), 1);
  const LidarScan scan = sim.SimulateScan([&](TimeNs) { return pose; }, t0, 0);
  const TrafficBox earlier = world.traffic().BoxesAt(0)[1];
  EXPECT_EQ(earlier.id, "passing");
  TrafficCounts n;
  for (const LidarPoint& p : *scan.points) {
    const Vec3 w = pose * Vec3(p.x, p.y, p.z);
    if (std::abs(w.z()) < 1e-3) {
      if (BoxDistance(earlier, Vec3(w.x(), w.y(), 0.75)) < 0.0) ++n.ground_at_old_place;
      continue;
    }
    double best = 1e9;
    std::string which;
    for (const TrafficBox& b : world.traffic().BoxesAt(t0 + FromSeconds(p.t))) {
      const double d = std::abs(BoxDistance(b, w));
      if (d < best) {
        best = d;
        which = b.id;
      }
    }
    EXPECT_LT(best, 1e-3) << "point at t=" << p.t << " is on no vehicle";
    (which == "passing" ? n.on_passing : n.on_leaving)++;
    if (BoxDistance(earlier, w) < 0.05) ++n.at_old_place;
  }
  return n;
}

TEST(LidarTraffic, VehiclesAppearAtTheirPosesAtEachColumnTime) {
  const GroundHeightFn flat = [](double, double) { return 0.0; };
  const auto world = LidarWorld::Build(MakeStraightRoad(-100.0, 100.0, 2, 3.5, flat), flat,
                                       testing::BareLayoutOptions());
  // SUMO-like steps of 100 ms: "passing" drives at 15 m/s on the far lane; "leaving" stands in
  // the near lane and is gone from the 1.1 s step on, so it vanishes at 1.05 s.
  std::vector<TrafficFrame> frames;
  for (int k = 0; k <= 20; ++k) {
    TrafficFrame f{TimeNs{k} * 100'000'000, {Car("passing", -15.0 + 1.5 * k, 5.25)}};
    if (k <= 10) f.boxes.push_back(Car("leaving", 12.0, -5.25, 0.1));
    frames.push_back(f);
  }
  world->SetTraffic(TrafficTimeline(frames));
  const SE3 pose(Quat::Identity(), Vec3(0.0, 0.0, 1.8));

  // Sweep 0.95-1.05 s: "passing" moves 1.5 m during it (seen at ~25 ms), "leaving" is seen at
  // ~57 ms (azimuth -24 deg), before it vanishes.
  const TrafficCounts a = ScanTraffic(*world, pose, 950'000'000);
  EXPECT_GT(a.on_passing, 100);
  EXPECT_GT(a.on_leaving, 100);
  EXPECT_EQ(a.at_old_place, 0);
  EXPECT_GT(a.ground_at_old_place, 20);  // where it was at t = 0 the ground is visible now

  // Sweep 1.0-1.1 s: the column towards "leaving" fires at ~1.057 s, after it vanished.
  const TrafficCounts b = ScanTraffic(*world, pose, 1'000'000'000);
  EXPECT_GT(b.on_passing, 100);
  EXPECT_EQ(b.on_leaving, 0);
}

}  // namespace
}  // namespace statebench::sensors
