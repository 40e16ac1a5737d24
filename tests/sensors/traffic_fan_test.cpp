// The lidar's traffic path (TrafficWindow::PoseFor once per column, then TrafficWindow::Cast per
// ray over the posed boxes) against the brute force over every vehicle at the firing time: the
// same hits with the same bits. And RayFan's culling never drops a ball a ray of the fan meets.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "sensors/lidar_beam_model.hpp"
#include "sensors/ray_fan.hpp"
#include "sensors/traffic_window.hpp"

namespace statebench::sensors {
namespace {

// 60 vehicles near the origin over 2 s of 100 ms steps, some of them leaving or arriving, with
// random sizes, headings, pitches and speeds.
TrafficTimeline FanTestTraffic(std::mt19937_64& rng) {
  std::vector<TrafficBox> start;
  std::vector<Vec3> velocity;
  for (int k = 0; k < 60; ++k) {
    TrafficBox b;
    b.id = "veh" + std::to_string(k);
    b.centre_world = Vec3(160.0 * Uniform01(rng) - 80.0, 160.0 * Uniform01(rng) - 80.0,
                          0.75 + 2.0 * Uniform01(rng) - 1.0);
    b.yaw_rad = 2.0 * M_PI * Uniform01(rng);
    b.pitch_rad = 0.1 * Uniform01(rng) - 0.05;
    b.length_m = 3.0 + 10.0 * Uniform01(rng);
    b.width_m = 1.5 + Uniform01(rng);
    b.height_m = 1.2 + 2.5 * Uniform01(rng);
    start.push_back(b);
    velocity.push_back(Vec3(30.0 * Uniform01(rng) - 15.0, 30.0 * Uniform01(rng) - 15.0, 0.0));
  }
  std::vector<TrafficFrame> frames;
  for (int step = 0; step <= 20; ++step) {
    TrafficFrame f{TimeNs{step} * 100'000'000, {}};
    for (std::size_t k = 0; k < start.size(); ++k) {
      if (k % 7 == 0 && step > 12) continue;  // gone
      if (k % 11 == 0 && step < 6) continue;  // not there yet
      TrafficBox b = start[k];
      b.centre_world += 0.1 * step * velocity[k];
      b.yaw_rad += 0.05 * step;
      f.boxes.push_back(b);
    }
    frames.push_back(f);
  }
  return TrafficTimeline(frames);
}

// Closest box at t_ns over every vehicle, the first on equal ranges (the window's order).
std::optional<RayHit> BruteForceTrafficCast(const TrafficTimeline& traffic, const Vec3& o,
                                            const Vec3& d, double max_range, TimeNs t_ns) {
  std::optional<RayHit> best;
  double best_range = max_range;
  for (const TrafficBox& box : traffic.BoxesAt(t_ns)) {
    if (auto hit = IntersectTrafficBox(box, o, d, best_range)) {
      if (!best || hit->range_m < best_range) {
        best_range = hit->range_m;
        best = hit;
      }
    }
  }
  return best;
}

TEST(TrafficFan, PosedColumnsCastLikeTheBruteForceBitForBit) {
  std::mt19937_64 rng = MakeRng(3, "traffic fan");
  const TrafficTimeline traffic = FanTestTraffic(rng);
  const LidarBeamModel beams = HesaiXt32BeamModel();
  std::vector<PosedTrafficBox> posed;
  int hits = 0;
  for (int sweep = 0; sweep < 8; ++sweep) {
    const TimeNs t0 = TimeNs{sweep} * 150'000'000;
    const TimeNs t1 = t0 + beams.PeriodNs();
    const TrafficWindow window(traffic, t0, t1);
    for (int c = 0; c < beams.columns; c += 7) {
      std::vector<Vec3> directions;
      for (int r = 0; r < beams.channels(); ++r) directions.push_back(beams.Direction(c, r));
      const RayFan fan = FanOf(directions);
      const Quat q = Quat(Eigen::AngleAxisd(2.0 * M_PI * Uniform01(rng), Vec3::UnitZ()) *
                          Eigen::AngleAxisd(0.2 * Uniform01(rng) - 0.1, Vec3::UnitX()));
      const Vec3 origin(60.0 * Uniform01(rng) - 30.0, 60.0 * Uniform01(rng) - 30.0,
                        1.9 + Uniform01(rng));
      const TimeNs t = t0 + beams.ColumnOffsetNs(c);
      window.PoseFor(fan.Rotated(q), origin, 120.0, t, &posed);
      for (const Vec3& d_lidar : directions) {
        const Vec3 d = q * d_lidar;
        // Half the rays with a shorter limit, as behind a static hit.
        const double max_range = Uniform01(rng) < 0.5 ? 120.0 : 120.0 * Uniform01(rng);
        const auto expected = BruteForceTrafficCast(traffic, origin, d, max_range, t);
        const auto got = TrafficWindow::Cast(posed, origin, d, max_range);
        ASSERT_EQ(got.has_value(), expected.has_value()) << "sweep " << sweep << " column " << c;
        if (!got) continue;
        ++hits;
        ASSERT_EQ(got->range_m, expected->range_m);
        ASSERT_EQ(got->normal_world, expected->normal_world);
        // The single-ray path agrees too.
        const auto single = window.Cast(origin, d, max_range, t);
        ASSERT_TRUE(single);
        ASSERT_EQ(single->range_m, expected->range_m);
      }
    }
  }
  EXPECT_GT(hits, 1000);
}

TEST(RayFan, NeverCullsABallARayOfTheFanMeets) {
  std::mt19937_64 rng = MakeRng(4, "ray fan");
  const LidarBeamModel beams = VelodyneVlp16BeamModel();
  int met = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const int c = static_cast<int>(Uniform01(rng) * beams.columns);
    std::vector<Vec3> directions;
    for (int r = 0; r < beams.channels(); ++r) directions.push_back(beams.Direction(c, r));
    const Quat q(Eigen::AngleAxisd(6.0 * Uniform01(rng),
                                   Vec3(Uniform01(rng), Uniform01(rng), 1.0).normalized()));
    const RayFan fan = FanOf(directions).Rotated(q);
    // A ball centred near a point of one of the rays, its radius just above the distance.
    const Vec3 d = q * directions[static_cast<std::size_t>(Uniform01(rng) * directions.size())];
    const double range = 100.0 * Uniform01(rng);
    const Vec3 offset = Vec3(Uniform01(rng) - 0.5, Uniform01(rng) - 0.5, Uniform01(rng) - 0.5);
    const Vec3 centre = Vec3(3.0, -2.0, 1.0) + range * d + offset;
    const double radius = offset.norm() * (1.0 + 1e-12);
    ASSERT_TRUE(fan.MayMeetBall(Vec3(3.0, -2.0, 1.0), 100.0, centre, radius)) << trial;
    ++met;
  }
  // Far off the column's plane or behind the sensor: culled.
  std::vector<Vec3> column;
  for (int r = 0; r < beams.channels(); ++r) column.push_back(beams.Direction(0, r));
  const RayFan fan = FanOf(column);
  const Vec3 ahead = column[8];
  EXPECT_TRUE(fan.MayMeetBall(Vec3::Zero(), 100.0, 50.0 * ahead, 1.0));
  EXPECT_FALSE(fan.MayMeetBall(Vec3::Zero(), 100.0, 50.0 * ahead + 5.0 * fan.normal, 1.0));
  EXPECT_FALSE(fan.MayMeetBall(Vec3::Zero(), 100.0, -50.0 * ahead, 1.0));
  EXPECT_FALSE(fan.MayMeetBall(Vec3::Zero(), 100.0, 150.0 * ahead, 1.0));
  EXPECT_EQ(met, 4000);
}

}  // namespace
}  // namespace statebench::sensors
