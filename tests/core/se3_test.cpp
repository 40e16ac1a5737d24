#include "core/se3.hpp"

#include <gtest/gtest.h>

#include <random>

namespace statebench {
namespace {

Vec6 RandomTwist(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 0.7);
  Vec6 xi;
  for (int i = 0; i < 6; ++i) xi[i] = n(rng);
  return xi;
}

TEST(Se3, ExpLogRoundTrip) {
  std::mt19937 rng(4);
  for (int i = 0; i < 100; ++i) {
    const Vec6 xi = RandomTwist(rng);
    EXPECT_LT((SE3::Exp(xi).Log() - xi).norm(), 1e-9) << i;
  }
}

TEST(Se3, ComposeInverseAndPoints) {
  std::mt19937 rng(5);
  const SE3 a = SE3::Exp(RandomTwist(rng));
  const SE3 b = SE3::Exp(RandomTwist(rng));
  const Vec3 p(1.0, -2.0, 0.5);
  EXPECT_LT(((a * b) * p - a * (b * p)).norm(), 1e-12);
  EXPECT_LT(((a * a.Inverse()).Log()).norm(), 1e-12);
  EXPECT_LT((a.Matrix() * b.Matrix() - (a * b).Matrix()).norm(), 1e-12);
}

TEST(Se3, BoxPlusMinusInvariants) {
  std::mt19937 rng(6);
  for (int i = 0; i < 50; ++i) {
    const SE3 x = SE3::Exp(RandomTwist(rng));
    const Vec6 d = 0.5 * RandomTwist(rng);
    const SE3 y = x * SE3::Exp(d);
    EXPECT_LT(((x.Inverse() * y).Log() - d).norm(), 1e-9);
  }
}

TEST(Se3, Interpolate) {
  const SE3 t0(so3::FromRollPitchYaw(0, 0, 0.2), Vec3(1, 2, 3));
  const SE3 t1(so3::FromRollPitchYaw(0.1, 0, 1.2), Vec3(3, 0, 3));
  EXPECT_LT((SE3::Interpolate(t0, t1, 0.0).Log() - t0.Log()).norm(), 1e-12);
  EXPECT_LT((SE3::Interpolate(t0, t1, 1.0).Log() - t1.Log()).norm(), 1e-9);
  // Pure translation interpolates linearly.
  const SE3 a(Quat::Identity(), Vec3(0, 0, 0)), b(Quat::Identity(), Vec3(2, 4, 6));
  EXPECT_LT((SE3::Interpolate(a, b, 0.25).translation() - Vec3(0.5, 1, 1.5)).norm(), 1e-12);
}

}  // namespace
}  // namespace statebench
