// The lidar as a SensorModel of the suite: sweeps on the period grid, emitted when complete with
// the right stamps and arrival, from poses interpolated between the 1 kHz truth samples that
// match the exact trajectory.
#include "sensors/lidar_sensor_model.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "lidar_test_fixtures.hpp"
#include "sensors/sensor_suite.hpp"
#include "sensors/synthetic_roads.hpp"
#include "truth_fixtures.hpp"

namespace statebench::sensors {
namespace {

constexpr double kGroundZ = 0.3;

std::unique_ptr<LidarWorld> FlatWorldWithWall() {
  const GroundHeightFn ground = [](double, double) { return kGroundZ; };
  WorldLayoutOptions layout = testing::BareLayoutOptions();
  WorldBox wall;  // something that is not the ground, 30 m east of the circle's centre
  wall.centre_world = Vec3(30.0, 0.0, kGroundZ + 4.0);
  wall.size_m = Vec3(2.0, 40.0, 8.0);
  layout.extra_boxes.push_back(wall);
  LidarWorldOptions options;
  options.ground_margin_m = 150.0;
  return LidarWorld::Build(MakeStraightRoad(-50.0, 50.0, 1, 3.5, ground), ground, layout, options);
}

SensorSpec LidarSpec() {
  SensorSpec spec;
  spec.id = "lidar_roof";
  spec.rate_hz = 10.0;
  spec.latency_s = 0.02;
  spec.T_body_sensor = SE3(so3::FromRollPitchYaw(0.0, 0.02, 0.1), Vec3(-0.15, 0.0, 1.62));
  return spec;
}

LidarOptions ExactOptions() {
  LidarOptions o = DefaultLidarOptions(LidarModel::kHesaiXt32);
  o.range_noise_sigma_m = 0.0;
  o.dropout_probability = 0.0;
  return o;
}

testing::Circle FastCircle() {
  testing::Circle c;
  c.radius_m = 12.0;
  c.speed_mps = 10.0;  // 0.83 rad/s: a strongly distorted sweep
  c.centre = Vec3(0.0, 0.0, kGroundZ);
  return c;
}

TEST(LidarSensorModel, EmitsEachSweepWhenCompleteWithStampAndArrival) {
  const auto world = FlatWorldWithWall();
  LidarSensorModel model(LidarSpec(), ExactOptions(), *world, 3);
  const testing::Circle circle = FastCircle();
  std::vector<Measurement> out;
  for (TimeNs t = 5 * kNsPerMillisecond; t <= 350 * kNsPerMillisecond; t += kNsPerMillisecond) {
    const std::size_t before = out.size();
    model.Observe(circle.At(t), &out);
    for (std::size_t i = before; i < out.size(); ++i) {
      // The contract SensorSuite relies on.
      EXPECT_GE(HeaderOf(out[i]).arrival_ns, t + model.MinArrivalDelayNs());
      EXPECT_EQ(t % (100 * kNsPerMillisecond), 0);
    }
  }
  // The first sweep starts at the first multiple of 100 ms after the first truth sample (100 ms);
  // the one from 300 ms is still open at 350 ms.
  ASSERT_EQ(out.size(), 2u);
  for (std::size_t k = 0; k < out.size(); ++k) {
    const auto& scan = std::get<LidarScan>(out[k]);
    EXPECT_EQ(scan.header.sensor_id, "lidar_roof");
    EXPECT_EQ(scan.header.stamp_ns, static_cast<TimeNs>(k + 1) * 100 * kNsPerMillisecond);
    EXPECT_EQ(scan.header.arrival_ns, scan.header.stamp_ns + 120 * kNsPerMillisecond);
    EXPECT_GT(scan.points->size(), 2000u * 16u);  // every downward beam at least
  }
}

TEST(LidarSensorModel, InterpolatedPosesMatchTheExactTrajectory) {
  const auto world = FlatWorldWithWall();
  const SensorSpec spec = LidarSpec();
  LidarSensorModel model(spec, ExactOptions(), *world, 3);
  const testing::Circle circle = FastCircle();
  std::vector<Measurement> out;
  for (TimeNs t = 0; t <= 200 * kNsPerMillisecond; t += kNsPerMillisecond) {
    model.Observe(circle.At(t), &out);
  }
  ASSERT_EQ(out.size(), 2u);
  // The same sweep from the exact circle pose at every column time.
  const LidarSimulator exact(*world, LidarParamsFromSetup(spec, ExactOptions(), "test"), 3);
  const LidarScan reference = exact.SimulateScanFromBody(
      [&](TimeNs t) { return circle.At(t).body.T_world_frame; }, 100 * kNsPerMillisecond, 1);
  const auto& scan = std::get<LidarScan>(out[1]);
  ASSERT_EQ(scan.points->size(), reference.points->size());
  double max_diff = 0.0;
  int wall_points = 0;
  for (std::size_t i = 0; i < scan.points->size(); ++i) {
    const LidarPoint& a = (*scan.points)[i];
    const LidarPoint& b = (*reference.points)[i];
    ASSERT_EQ(a.ring, b.ring);
    ASSERT_EQ(a.t, b.t);
    max_diff = std::max(max_diff, (Vec3(a.x, a.y, a.z) - Vec3(b.x, b.y, b.z)).norm());
    wall_points += std::abs(a.z) < 1.0 && Vec3(a.x, a.y, a.z).norm() > 10.0 ? 1 : 0;
  }
  RecordProperty("max_point_difference_m", std::to_string(max_diff));
  EXPECT_LT(max_diff, 1e-4);    // sub-millimetre: interpolation error and float rounding
  EXPECT_GT(wall_points, 500);  // the sweep saw the wall, not only the ground
}

TEST(LidarSensorModel, JoinsTheSuiteStreamInArrivalOrder) {
  const auto world = FlatWorldWithWall();
  SensorSetup setup;
  setup.name = "imu_and_lidar";
  SensorSpec imu_spec;
  imu_spec.id = "imu";
  imu_spec.rate_hz = 100.0;
  imu_spec.latency_s = 0.002;
  setup.sensors.push_back({imu_spec, ImuOptions{}, "test"});
  SensorSuite suite(setup, LocalEnuFrame(GeodeticPoint{48.0, 2.0, 100.0}), 5);
  suite.AddModel(std::make_unique<LidarSensorModel>(LidarSpec(), ExactOptions(), *world, 5));
  const testing::Circle circle = FastCircle();
  std::vector<Measurement> stream;
  for (TimeNs t = 0; t <= 500 * kNsPerMillisecond; t += kNsPerMillisecond) {
    suite.Push(circle.At(t), &stream);
  }
  suite.Finish(&stream);
  int scans = 0;
  for (std::size_t i = 0; i < stream.size(); ++i) {
    if (i > 0) {
      EXPECT_FALSE(ArrivesBefore(stream[i], stream[i - 1])) << i;
    }
    scans += std::holds_alternative<LidarScan>(stream[i]) ? 1 : 0;
  }
  EXPECT_EQ(scans, 5);
}

TEST(LidarSensorModel, RejectsRatesTheHeadCannotSpin) {
  const auto world = FlatWorldWithWall();
  SensorSpec spec = LidarSpec();
  spec.rate_hz = 5.0;
  EXPECT_THROW(LidarSensorModel(spec, ExactOptions(), *world, 1, "setup.yaml:7:5"), InputError);
}

}  // namespace
}  // namespace statebench::sensors
