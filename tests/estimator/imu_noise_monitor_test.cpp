// The IMU noise the estimator measures (imu_noise_monitor.hpp): a consumer IMU beside an idle
// engine reads as the white noise that spreads 0.1 s means as its tones and datasheet noise do
// (the tones' rms through the analytic Hadamard variance of their means, within 10 %), and
// inflates the configured density to it; an IMU as noisy as its datasheet leaves the configured
// density in use.
#include "estimator/imu_noise_monitor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/random.hpp"
#include "core/state.hpp"
#include "idle_tone.hpp"

namespace statebench::est {
namespace {

constexpr double kMonitorDt = 0.01;  // 100 Hz

// Feeds duration_s of a standing IMU (white noise of `white`, the idle tone when `tone`).
ImuNoiseMonitor Feed(const ImuNoiseEstimationOptions& options, const ImuNoise& configured,
                     const ImuNoise& white, bool tone, std::uint64_t seed, double duration_s) {
  ImuNoiseMonitor monitor(options, configured);
  const testing::IdleTone idle(seed);
  auto rng = MakeRng(seed, "noise_monitor");
  NormalSampler normal;
  const auto r3 = [&] { return Vec3(normal(rng), normal(rng), normal(rng)); };
  for (int k = 0; k * kMonitorDt <= duration_s; ++k) {
    ImuSample s;
    s.header.stamp_ns = FromSeconds(k * kMonitorDt);
    s.gyro = white.gyro_noise_density / std::sqrt(kMonitorDt) * r3();
    s.accel = Vec3(0.0, 0.0, kGravity) + white.accel_noise_density / std::sqrt(kMonitorDt) * r3();
    if (tone) idle.Add(k * kMonitorDt, &s);
    monitor.AddStill(s);
  }
  return monitor;
}

// What the monitor should read (scale 0.1 s = 10 samples): a tone of rms a at f Hz has means
// over the span of rms G a, G = |sin(pi f N dt) / (N sin(pi f dt))|, advancing by
// theta = 2 pi f N dt per span; their second differences have rms (2 - 2 cos theta) G a, and the
// Hadamard variance is a sixth of its square. density^2 = H x span + the white density^2.
double ExpectedDensity(const Vec3& rms2, const Vec3& rms1, double f2, double f1, double white) {
  const int n = 10;
  const double T = n * kMonitorDt;
  const auto h = [&](double f) {
    const double g = std::abs(std::sin(std::numbers::pi * f * T) /
                              (n * std::sin(std::numbers::pi * f * kMonitorDt)));
    const double d = 2.0 - 2.0 * std::cos(2.0 * std::numbers::pi * f * T);
    return d * d * g * g / 6.0;
  };
  const double tones = (h(f2) * rms2.cwiseAbs2() + h(f1) * rms1.cwiseAbs2()).mean();
  return std::sqrt(tones * T + white * white);
}

TEST(ImuNoiseMonitor, IdleEngineInflatesToTheToneRms) {
  const ImuNoise consumer{2.4e-4, 2e-3};
  const testing::IdleTone idle(0);
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const ImuNoiseMonitor m = Feed({}, ImuNoise{}, consumer, true, seed, 30.0);
    const ImuNoiseReport& r = m.report();
    const double gyro = ExpectedDensity(idle.gyro_rms2, idle.gyro_rms1, idle.order2_hz,
                                        idle.order1_hz, consumer.gyro_noise_density);
    const double accel = ExpectedDensity(idle.accel_rms2, idle.accel_rms1, idle.order2_hz,
                                         idle.order1_hz, consumer.accel_noise_density);
    std::printf("seed %d: gyro %.3g (expected %.3g), accel %.3g (expected %.3g)\n",
                static_cast<int>(seed), r.gyro_measured, gyro, r.accel_measured, accel);
    EXPECT_EQ(r.blocks, 29);  // 30 s of samples: 29 whole blocks of 101 samples (1 s)
    EXPECT_NEAR(r.gyro_measured, gyro, 0.1 * gyro) << seed;
    EXPECT_NEAR(r.accel_measured, accel, 0.1 * accel) << seed;
    EXPECT_EQ(m.used().gyro_noise_density, r.gyro_measured);
    EXPECT_EQ(m.used().accel_noise_density, r.accel_measured);
    EXPECT_EQ(m.used().gyro_random_walk, ImuNoise{}.gyro_random_walk);
  }
}

TEST(ImuNoiseMonitor, TheDatasheetIsKeptWhenTheNoiseMatchesIt) {
  const ImuNoise industrial;  // the defaults, and the IMU as noisy as they say
  const ImuNoiseMonitor m = Feed({}, industrial, industrial, false, 4, 30.0);
  EXPECT_NEAR(m.report().gyro_measured, industrial.gyro_noise_density,
              0.15 * industrial.gyro_noise_density);
  EXPECT_NEAR(m.report().accel_measured, industrial.accel_noise_density,
              0.15 * industrial.accel_noise_density);
  EXPECT_EQ(m.used().gyro_noise_density, industrial.gyro_noise_density);
  EXPECT_EQ(m.used().accel_noise_density, industrial.accel_noise_density);
}

TEST(ImuNoiseMonitor, InflationIsBoundedAndCanBeOff) {
  ImuNoiseEstimationOptions bounded;
  bounded.max_inflation = 5.0;
  const ImuNoiseMonitor m = Feed(bounded, ImuNoise{}, ImuNoise{2.4e-4, 2e-3}, true, 5, 5.0);
  EXPECT_EQ(m.used().gyro_noise_density, 5.0 * ImuNoise{}.gyro_noise_density);
  EXPECT_EQ(m.report().gyro_used_max, 5.0 * ImuNoise{}.gyro_noise_density);
  ImuNoiseEstimationOptions off;
  off.enabled = false;
  const ImuNoiseMonitor n = Feed(off, ImuNoise{}, ImuNoise{2.4e-4, 2e-3}, true, 5, 5.0);
  EXPECT_EQ(n.report().blocks, 0);
  EXPECT_EQ(n.used().gyro_noise_density, ImuNoise{}.gyro_noise_density);
}

}  // namespace
}  // namespace statebench::est
