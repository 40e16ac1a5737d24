#include "core/random.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace statebench {
namespace {

TEST(Random, StreamsAreReproducibleAndIndependent) {
  auto a1 = MakeRng(42, "imu"), a2 = MakeRng(42, "imu"), b = MakeRng(42, "gnss_front");
  auto c = MakeRng(43, "imu");
  const auto x = a1();
  EXPECT_EQ(x, a2());
  EXPECT_NE(x, b());
  EXPECT_NE(x, c());
}

TEST(Random, NormalSamplerMoments) {
  auto rng = MakeRng(7, "normal");
  NormalSampler normal;
  double sum = 0, sum_sq = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double v = normal(rng);
    sum += v;
    sum_sq += v * v;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.01);
  EXPECT_NEAR(std::sqrt(sum_sq / n), 1.0, 0.01);
}

}  // namespace
}  // namespace statebench
