// The rolling IMU window of the standstill tests (imu_still_window.hpp): it keeps the newest
// window_s whatever else arrives, and a span between two odometry messages (~10 samples, too
// short for the low band) is tested over it: with an idle tone on a standing IMU the span alone
// is never quiet, the rolling window is.
#include "estimator/imu_still_window.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace statebench::est {
namespace {

// A standing IMU at 100 Hz with a 26.7 Hz idle tone of 0.03 rad/s and 0.3 m/s^2 rms.
ImuSample IdleSample(int k) {
  const double t = 0.01 * k;
  const double tone = std::sqrt(2.0) * std::sin(2.0 * std::numbers::pi * 26.7 * t + 0.3);
  ImuSample s;
  s.header.stamp_ns = FromSeconds(t);
  s.gyro = Vec3::Constant(0.03 * tone);
  s.accel = Vec3(0.0, 0.0, 9.81) + Vec3::Constant(0.3 * tone);
  return s;
}

TEST(ImuStillWindow, KeepsTheNewestWindowAndNeedsMostOfIt) {
  const ZeroVelocityOptions z;  // window_s 0.3
  ImuStillWindow w(z.window_s);
  for (int k = 0; k < 27; ++k) w.Push(IdleSample(k));
  EXPECT_FALSE(w.Statistics(z));  // 0.26 s: less than 0.9 window_s
  w.Push(IdleSample(27));
  EXPECT_TRUE(w.Statistics(z));
  for (int k = 28; k < 200; ++k) w.Push(IdleSample(k));
  EXPECT_EQ(w.samples().size(), 31u);  // 0.30 s inclusive
  EXPECT_EQ(w.samples().front().header.stamp_ns, FromSeconds(1.69));
  w.Clear();
  EXPECT_FALSE(w.Statistics(z));
}

TEST(ImuStillWindow, AnOdometrySpanIsTestedOverTheRollingWindow) {
  const ZeroVelocityOptions z;
  ImuStillWindow w(z.window_s);
  std::vector<ImuSample> span;  // the samples since the previous 10 Hz odometry message
  for (int k = 0; k < 100; ++k) {
    w.Push(IdleSample(k));
    if (k >= 90) span.push_back(IdleSample(k));
  }
  // The span alone: its low band is not valid (10 samples) and its raw samples shake.
  EXPECT_FALSE(ComputeImuWindowStatistics(span, z).Quiet(z));
  const std::optional<ImuWindowStatistics> still = StillSpanStatistics(span, w, z);
  ASSERT_TRUE(still);
  EXPECT_TRUE(still->bands.valid());
  EXPECT_TRUE(still->Quiet(z));
  // A span at least window_s long is tested over itself.
  std::vector<ImuSample> long_span;
  for (int k = 60; k < 100; ++k) long_span.push_back(IdleSample(k));
  const std::optional<ImuWindowStatistics> own = StillSpanStatistics(long_span, w, z);
  ASSERT_TRUE(own);
  EXPECT_EQ(own->mean_gyro, ComputeImuWindowStatistics(long_span, z).mean_gyro);
}

}  // namespace
}  // namespace statebench::est
