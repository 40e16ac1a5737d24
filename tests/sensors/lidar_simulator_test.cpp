#include "sensors/lidar_simulator.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>

#include "core/so3.hpp"
#include "lidar_test_fixtures.hpp"
#include "sensors/synthetic_roads.hpp"

namespace statebench::sensors {
namespace {

using testing::BareLayoutOptions;
using testing::ExactLidar;
using testing::FlatWorld;

constexpr double kPlaneZ = 2.5;
constexpr double kSensorHeight = 1.8;

Vec3 ToWorld(const SE3& T_world_lidar, const LidarPoint& p) {
  return T_world_lidar * Vec3(p.x, p.y, p.z);
}

TEST(LidarSimulator, StaticSensorOverPlaneGetsExactRanges) {
  const auto world = FlatWorld(kPlaneZ);
  for (const std::string model : {"hesai_xt32", "velodyne_vlp16"}) {
    const LidarSimulator sim(*world, ExactLidar(model), 1);
    const LidarBeamModel& beams = sim.params().beams;
    const SE3 pose(Quat::Identity(), Vec3(3.0, -1.0, kPlaneZ + kSensorHeight));
    const LidarScan scan = sim.SimulateScan([&](TimeNs) { return pose; }, 0, 0);

    // Every downward beam whose ground range is within max range returns (VLP-16's -1 deg beam
    // reaches the ground at 103 m, beyond its 100 m).
    int seen_rings = 0;
    for (const double e : beams.elevations_rad) {
      seen_rings += e < 0.0 && kSensorHeight / std::sin(-e) <= sim.params().max_range_m ? 1 : 0;
    }
    ASSERT_EQ(static_cast<int>(scan.points->size()), beams.columns * seen_rings) << model;
    double max_error = 0.0;
    for (const LidarPoint& p : *scan.points) {
      const double elevation = beams.elevations_rad[p.ring];
      ASSERT_LT(elevation, 0.0);
      const double expected = kSensorHeight / std::sin(-elevation);
      const double range = Vec3(p.x, p.y, p.z).norm();
      max_error = std::max(max_error, std::abs(range - expected));
      EXPECT_GT(p.intensity, 0.f);
    }
    EXPECT_LT(max_error, 1e-3) << model;
    RecordProperty(model + "_max_range_error_m", std::to_string(max_error));
  }
}

TEST(LidarSimulator, PointTimesAndRingsFollowTheColumns) {
  const auto world = FlatWorld(0.0);
  const LidarSimulator sim(*world, ExactLidar("hesai_xt32"), 1);
  const SE3 pose(Quat::Identity(), Vec3(0.0, 0.0, kSensorHeight));
  const TimeNs t0 = 5'000'000'000;
  const LidarScan scan = sim.SimulateScan([&](TimeNs) { return pose; }, t0, 3);
  EXPECT_EQ(scan.header.stamp_ns, t0);
  EXPECT_EQ(scan.header.arrival_ns, t0 + 100'000'000);
  EXPECT_EQ(scan.header.sensor_id, "lidar_test");
  // Column-major, rings ascending: 16 downward rings per column.
  const auto& pts = *scan.points;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const int column = static_cast<int>(i / 16);
    EXPECT_EQ(pts[i].ring, i % 16);
    EXPECT_FLOAT_EQ(pts[i].t, static_cast<float>(column * 50e-6));
  }
}

// Vehicle-like motion: forward 10 m/s with a yaw rate, rolling and pitching, bouncing.
SE3 MovingPose(TimeNs t_ns) {
  const double t = ToSeconds(t_ns);
  const double yaw = 0.3 + 0.8 * t;
  const Quat q = so3::FromRollPitchYaw(0.05 * std::sin(9.0 * t), 0.04 * std::cos(7.0 * t), yaw);
  // Position: integral of 10 m/s along the heading, in closed form.
  const Vec3 p(-10.0 + 10.0 / 0.8 * (std::sin(yaw) - std::sin(0.3)),
               10.0 / 0.8 * (std::cos(0.3) - std::cos(yaw)),
               kSensorHeight + 0.05 * std::sin(11.0 * t));
  return SE3(q, p);
}

TEST(LidarSimulator, MovingSensorPointsDeskewedWithTruthLandOnTheSurfaces) {
  // Ground z = 0 and a long wall whose front face is the plane x = 25.
  WorldBox wall;
  wall.centre_world = Vec3(25.5, 0.0, 4.0);
  wall.size_m = Vec3(1.0, 300.0, 10.0);
  const auto world = FlatWorld(0.0, {wall});
  const LidarSimulator sim(*world, ExactLidar("hesai_xt32"), 1);

  const TimeNs t0 = 200'000'000;
  const LidarScan scan = sim.SimulateScan(MovingPose, t0, 0);
  double max_error = 0.0;
  double max_error_skewed = 0.0;
  int on_wall = 0, on_ground = 0;
  for (const LidarPoint& p : *scan.points) {
    const Vec3 deskewed = ToWorld(MovingPose(t0 + FromSeconds(p.t)), p);
    const double to_ground = std::abs(deskewed.z());
    const double to_wall = std::abs(deskewed.x() - 25.0);
    max_error = std::max(max_error, std::min(to_ground, to_wall));
    (to_wall < to_ground ? on_wall : on_ground)++;
    const Vec3 skewed = ToWorld(MovingPose(t0), p);
    max_error_skewed =
        std::max(max_error_skewed, std::min(std::abs(skewed.z()), std::abs(skewed.x() - 25.0)));
  }
  EXPECT_GT(on_wall, 3000);
  EXPECT_GT(on_ground, 10000);
  EXPECT_LT(max_error, 1e-3);
  // Without deskewing, the motion during the sweep shows: the test can fail.
  EXPECT_GT(max_error_skewed, 0.1);
  RecordProperty("max_deskew_error_m", std::to_string(max_error));
}

TEST(LidarSimulator, NoiseAndDropoutAreSeededPerScanAndThreadIndependent) {
  const auto world = FlatWorld(0.0);
  LidarModelParams params = ExactLidar("hesai_xt32");
  params.range_noise_sigma_m = 0.01;
  params.dropout_probability = 0.1;
  const LidarSimulator sim(*world, params, 42);
  const SE3 pose(Quat::Identity(), Vec3(0.0, 0.0, kSensorHeight));
  const auto fixed = [&](TimeNs) { return pose; };

  LidarScan one_thread, two_threads;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one_thread = sim.SimulateScan(fixed, 0, 7);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two_threads = sim.SimulateScan(fixed, 0, 7);
  }
  ASSERT_EQ(one_thread.points->size(), two_threads.points->size());
  for (std::size_t i = 0; i < one_thread.points->size(); ++i) {
    const LidarPoint& a = (*one_thread.points)[i];
    const LidarPoint& b = (*two_threads.points)[i];
    ASSERT_TRUE(a.x == b.x && a.y == b.y && a.z == b.z && a.t == b.t && a.ring == b.ring);
  }
  const LidarScan other_scan = sim.SimulateScan(fixed, 0, 8);
  EXPECT_NE((*other_scan.points)[0].x, (*one_thread.points)[0].x);

  // Statistics: 16 downward rings x 2000 columns, 10 % dropped, sigma 1 cm along the beam.
  const double n_beams = 32000.0;
  const double kept = static_cast<double>(one_thread.points->size()) / n_beams;
  EXPECT_NEAR(kept, 0.9, 0.01);  // binomial sd 0.0017
  double sum = 0.0, sum_sq = 0.0;
  for (const LidarPoint& p : *one_thread.points) {
    const double elevation = sim.params().beams.elevations_rad[p.ring];
    const double e = Vec3(p.x, p.y, p.z).norm() - kSensorHeight / std::sin(-elevation);
    sum += e;
    sum_sq += e * e;
  }
  const double n = static_cast<double>(one_thread.points->size());
  EXPECT_NEAR(sum / n, 0.0, 3e-4);
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.01, 0.0005);
}

TEST(LidarSimulator, ReflectivityLimitDropsFarGrazingGround) {
  const auto world = FlatWorld(0.0);
  LidarModelParams params = ExactLidar("hesai_xt32");
  params.range_at_10pct_m = 80.0;
  const LidarSimulator sim(*world, params, 1);
  const SE3 pose(Quat::Identity(), Vec3(0.0, 0.0, kSensorHeight));
  const LidarScan scan = sim.SimulateScan([&](TimeNs) { return pose; }, 0, 0);
  // Ground (asphalt 0.15 or soil 0.30) seen at -e: limit 80 sqrt(rho sin(e) / 0.1), range
  // 1.8 / sin(e). The -16 deg ring (6.5 m) stays; the -1 deg ring (103 m) is gone.
  bool ring0 = false, ring15 = false;
  for (const LidarPoint& p : *scan.points) {
    ring0 |= p.ring == 0;
    ring15 |= p.ring == 15;
  }
  EXPECT_TRUE(ring0);
  EXPECT_FALSE(ring15);
}

}  // namespace
}  // namespace statebench::sensors
