// The IMU band split (imu_band_split.hpp): the low band keeps what the triangle should of white
// noise, next to nothing of an idle tone, and slow motion whole.
#include "estimator/imu_band_split.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/random.hpp"

namespace statebench::est {
namespace {

constexpr double kBandDt = 0.01;  // 100 Hz

std::vector<Vec3> Signal(int n, double white_sigma, double tone_rms, double tone_hz,
                         std::uint64_t seed) {
  auto rng = MakeRng(seed, "band_split");
  NormalSampler normal;
  std::vector<Vec3> x;
  for (int k = 0; k < n; ++k) {
    const double tone =
        std::sqrt(2.0) * tone_rms * std::sin(2.0 * std::numbers::pi * tone_hz * k * kBandDt + 0.3);
    x.push_back(Vec3::Constant(tone) + white_sigma * Vec3(normal(rng), normal(rng), normal(rng)));
  }
  return x;
}

TEST(ImuBandSplit, WhiteNoiseKeepsTheTrianglesShare) {
  const ImuBand b = SplitImuBand(Signal(6000, 0.01, 0.0, 0.0, 3), LowPassTaps(0.1, kBandDt));
  ASSERT_TRUE(b.valid);
  for (int a = 0; a < 3; ++a) {
    // The triangle keeps sqrt((2 taps^2 + 1) / (3 taps^3)) = 0.259 of the sigma.
    EXPECT_NEAR(b.lowpass_std[a], 0.01 * 0.259, 0.01 * 0.03);
  }
}

TEST(ImuBandSplit, IdleToneLeavesTheLowBand) {
  const ImuBand b = SplitImuBand(Signal(30, 0.0, 0.03, 800.0 / 30.0, 3), LowPassTaps(0.1, kBandDt));
  ASSERT_TRUE(b.valid);  // a 0.3 s window
  EXPECT_LT(b.lowpass_std.maxCoeff(), 0.001);  // 0.0135 x the rms
}

TEST(ImuBandSplit, SlowMotionStaysInTheLowBand) {
  const ImuBand b = SplitImuBand(Signal(1000, 0.0, 0.1, 0.5, 3), LowPassTaps(0.1, kBandDt));
  EXPECT_NEAR(b.lowpass_std.mean(), 0.1, 0.01);  // 0.5 Hz: gain 0.99
}

TEST(ImuBandSplit, TooShortOrNoFilterIsNotValid) {
  EXPECT_FALSE(SplitImuBand(Signal(20, 0.01, 0.0, 0.0, 3), 10).valid);  // fewer than 21
  EXPECT_TRUE(SplitImuBand(Signal(21, 0.01, 0.0, 0.0, 3), 10).valid);
  EXPECT_FALSE(SplitImuBand(Signal(100, 0.01, 0.0, 0.0, 3), 1).valid);
  EXPECT_EQ(LowPassTaps(0.1, 0.01), 10);
  EXPECT_EQ(LowPassTaps(0.0, 0.01), 1);
}

}  // namespace
}  // namespace statebench::est
