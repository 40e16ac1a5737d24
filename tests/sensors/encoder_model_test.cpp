#include "sensors/encoder_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "truth_fixtures.hpp"

namespace statebench::sensors {
namespace {

SensorSpec EncoderSpec(const std::string& id, double rate_hz, const SE3& mount = SE3()) {
  SensorSpec spec;
  spec.id = id;
  spec.rate_hz = rate_hz;
  spec.T_body_sensor = mount;
  spec.latency_s = 0.01;
  return spec;
}

// Runs a model over `seconds` of truth at 1 kHz.
template <typename TruthFn>
std::vector<Measurement> RunModel(SensorModel& model, double seconds, TruthFn truth_at) {
  std::vector<Measurement> out;
  for (TimeNs t = 0; t <= FromSeconds(seconds); t += kNsPerMillisecond) {
    model.Observe(truth_at(t), &out);
  }
  return out;
}

// 100 ticks per revolution at 50 Hz: one tick per sample is 2 pi / 100 / 0.02 = 3.14 rad/s, so
// each sample is a whole number of those; the radius error scales the mean speed by 1/(1+e);
// the count does not drift (the sum of ticks is the wheel angle within one tick).
TEST(WheelEncoderModel, QuantisesToTicksAndAppliesTheRadiusError) {
  WheelEncoderOptions o;
  o.ticks_per_rev = 100;
  o.radius_error = {0.0, 0.02, -0.01, 0.05};
  WheelEncoderModel model(EncoderSpec("wheels", 50.0), o, 3);
  testing::Circle circle;  // 5 m/s, wheel radius 0.28 m: 17.857 rad/s
  const double seconds = 20.0;
  const auto out = RunModel(model, seconds, [&](TimeNs t) { return circle.At(t); });
  ASSERT_EQ(out.size(), 1000u);  // 50 Hz from the second sample time on
  const double quantum = 2.0 * std::numbers::pi / 100.0 / 0.02;
  const double omega_true = circle.speed_mps / circle.wheel_radius_m;
  std::array<double, 4> sum{};
  for (const Measurement& m : out) {
    const auto& w = std::get<WheelSpeeds>(m);
    EXPECT_EQ(w.header.arrival_ns - w.header.stamp_ns, 10 * kNsPerMillisecond);
    for (int i = 0; i < 4; ++i) {
      const double ticks = w.omega_radps[i] / quantum;
      EXPECT_NEAR(ticks, std::round(ticks), 1e-9);
      const double expected = omega_true / (1.0 + o.radius_error[i]);
      EXPECT_LE(std::abs(w.omega_radps[i] - expected), quantum + 1e-9);
      sum[i] += w.omega_radps[i];
    }
  }
  for (int i = 0; i < 4; ++i) {
    const double mean = sum[i] / out.size();
    const double expected = omega_true / (1.0 + o.radius_error[i]);
    // One tick over the 20 s span at most: 2 pi / 100 / 20 = 0.0031 rad/s.
    EXPECT_NEAR(mean, expected, 2.0 * std::numbers::pi / 100.0 / seconds + 1e-9) << i;
  }
}

TEST(SpeedEncoderModel, QuantisesDistanceTicksAndAppliesTheRadiusError) {
  SpeedEncoderOptions o;
  o.distance_per_tick_m = 0.02;
  o.radius_error = 0.03;
  // Mounted at the rear axle centre: the body x speed there equals the body origin's on a
  // circle (the lever arm is along x, the yaw rate only adds lateral velocity).
  SpeedEncoderModel model(EncoderSpec("speed", 100.0, SE3(Quat::Identity(), Vec3(-0.89, 0, 0.28))),
                          o, 4);
  testing::Circle circle;
  const auto out = RunModel(model, 10.0, [&](TimeNs t) { return circle.At(t); });
  ASSERT_EQ(out.size(), 1000u);
  const double quantum = 0.02 / 0.01;
  const double expected = circle.speed_mps / 1.03;
  double sum = 0.0;
  for (const Measurement& m : out) {
    const double v = std::get<VehicleSpeed>(m).speed_mps;
    EXPECT_NEAR(v / quantum, std::round(v / quantum), 1e-9);
    EXPECT_LE(std::abs(v - expected), quantum + 1e-9);
    sum += v;
  }
  EXPECT_NEAR(sum / out.size(), expected, 0.02 / 10.0 + 1e-9);
}

TEST(SpeedEncoderModel, ReversingGivesNegativeSpeed) {
  SpeedEncoderOptions o;
  o.distance_per_tick_m = 0.01;
  SpeedEncoderModel model(EncoderSpec("speed", 50.0), o, 4);
  const auto out = RunModel(model, 2.0, [](TimeNs t) {
    TruthSample s = testing::StaticTruth(t);
    s.body.v_world = Vec3(-1.5, 0.0, 0.0);
    return s;
  });
  double sum = 0.0;
  for (const Measurement& m : out) sum += std::get<VehicleSpeed>(m).speed_mps;
  EXPECT_NEAR(sum / out.size(), -1.5, 0.01 / 2.0 + 1e-9);
}

TEST(SteeringEncoderModel, OffsetAndResolutionAreApplied) {
  SteeringEncoderOptions o;
  o.resolution_rad = 0.001;
  o.offset_rad = 0.0123;
  SteeringEncoderModel model(EncoderSpec("steering", 100.0), o, 5);
  testing::Circle circle;  // delta = atan(1.69 / 20) = 0.08430 rad
  const auto out = RunModel(model, 1.0, [&](TimeNs t) { return circle.At(t); });
  ASSERT_EQ(out.size(), 101u);
  const double delta = std::atan(circle.wheelbase_m / circle.radius_m);
  for (const Measurement& m : out) {
    const double a = std::get<SteeringAngle>(m).angle_rad;
    EXPECT_DOUBLE_EQ(a, std::round((delta + o.offset_rad) / 0.001) * 0.001);
  }
}

TEST(SteeringEncoderModel, NoiseAveragesToTheOffsetAngle) {
  SteeringEncoderOptions o;
  o.offset_rad = -0.01;
  o.noise_sigma_rad = 0.002;
  SteeringEncoderModel model(EncoderSpec("steering", 100.0), o, 6);
  const auto out = RunModel(model, 60.0, [](TimeNs t) {
    TruthSample s = testing::StaticTruth(t);
    s.steering_front_rad = 0.2;
    return s;
  });
  double sum = 0.0, sum2 = 0.0;
  for (const Measurement& m : out) {
    const double e = std::get<SteeringAngle>(m).angle_rad - 0.19;
    sum += e;
    sum2 += e * e;
  }
  const double n = out.size();
  EXPECT_NEAR(sum / n, 0.0, 1e-4);  // 6001 samples: std of the mean 2.6e-5
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.002, 1e-4);
}

}  // namespace
}  // namespace statebench::sensors
