#include "core/so3.hpp"

#include <gtest/gtest.h>

#include <random>

namespace statebench {
namespace {

Vec3 RandomVec(std::mt19937& rng, double scale) {
  std::normal_distribution<double> n(0.0, scale);
  return Vec3(n(rng), n(rng), n(rng));
}

TEST(So3, ExpLogRoundTrip) {
  std::mt19937 rng(1);
  for (int i = 0; i < 200; ++i) {
    Vec3 phi = RandomVec(rng, 1.0);
    if (phi.norm() > 3.1) phi *= 3.0 / phi.norm();
    EXPECT_LT((so3::Log<double>(so3::Exp<double>(phi)) - phi).norm(), 1e-10) << i;
  }
  // Small angles go through the Taylor branch.
  const Vec3 tiny(1e-7, -2e-7, 3e-8);
  EXPECT_LT((so3::Log<double>(so3::Exp<double>(tiny)) - tiny).norm(), 1e-15);
}

TEST(So3, ExpMatchesAngleAxis) {
  const Vec3 axis = Vec3(1, 2, -1).normalized();
  const double angle = 0.7;
  const Quat expected(Eigen::AngleAxisd(angle, axis));
  EXPECT_TRUE(so3::Exp<double>(axis * angle).isApprox(expected, 1e-12));
}

TEST(So3, HatVee) {
  const Vec3 a(0.3, -1.2, 2.0), b(-0.5, 0.1, 0.9);
  EXPECT_LT((so3::Hat(a) * b - a.cross(b)).norm(), 1e-15);
  EXPECT_LT((so3::Vee(so3::Hat(a)) - a).norm(), 1e-15);
}

// Exp(phi + dphi) ~= Exp(phi) Exp(Jr(phi) dphi), checked by finite differences.
TEST(So3, RightJacobianNumeric) {
  std::mt19937 rng(2);
  for (int i = 0; i < 50; ++i) {
    const Vec3 phi = RandomVec(rng, 0.8);
    const Mat3 jr = so3::RightJacobian(phi);
    Mat3 numeric;
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
      const Vec3 d = Vec3::Unit(k) * h;
      numeric.col(k) =
          so3::Log<double>(so3::Exp<double>(phi).conjugate() * so3::Exp<double>(phi + d)) / h;
    }
    EXPECT_LT((numeric - jr).norm(), 1e-5) << i;
    EXPECT_LT((so3::RightJacobianInverse(phi) * jr - Mat3::Identity()).norm(), 1e-10);
  }
  EXPECT_LT((so3::RightJacobian(Vec3::Zero()) - Mat3::Identity()).norm(), 1e-15);
}

// Manifold invariants: Plus/Minus are inverse, Minus(x, x) = 0.
TEST(So3, BoxPlusMinusInvariants) {
  std::mt19937 rng(3);
  for (int i = 0; i < 50; ++i) {
    const Quat x = so3::Exp<double>(RandomVec(rng, 1.0));
    const Vec3 d = RandomVec(rng, 0.5);
    const Quat y = x * so3::Exp<double>(d);
    EXPECT_LT((so3::Log<double>(x.conjugate() * y) - d).norm(), 1e-10);
    EXPECT_LT(so3::Log<double>(x.conjugate() * x).norm(), 1e-15);
  }
}

TEST(So3, InterpolateEndpointsAndMidpoint) {
  const Quat q0 = so3::FromRollPitchYaw(0.1, -0.2, 0.3);
  const Quat q1 = so3::FromRollPitchYaw(0.4, 0.1, -1.0);
  EXPECT_TRUE(so3::Interpolate(q0, q1, 0.0).isApprox(q0, 1e-12));
  EXPECT_TRUE(so3::Interpolate(q0, q1, 1.0).isApprox(q1, 1e-12) ||
              so3::Interpolate(q0, q1, 1.0).coeffs().isApprox(-q1.coeffs(), 1e-12));
  const Quat mid = so3::Interpolate(q0, q1, 0.5);
  EXPECT_NEAR(q0.angularDistance(mid), mid.angularDistance(q1), 1e-12);
}

TEST(So3, RollPitchYawAndWrap) {
  const Vec3 rpy(0.2, -0.4, 2.9);
  EXPECT_LT((so3::ToRollPitchYaw(so3::FromRollPitchYaw(rpy.x(), rpy.y(), rpy.z())) - rpy).norm(),
            1e-12);
  EXPECT_NEAR(so3::WrapAngle(3.5), 3.5 - 2 * M_PI, 1e-15);
  EXPECT_NEAR(so3::WrapAngle(-3.5), -3.5 + 2 * M_PI, 1e-15);
  EXPECT_NEAR(so3::WrapAngle(M_PI), M_PI, 1e-15);
  EXPECT_NEAR(so3::WrapAngle(-M_PI), M_PI, 1e-15);
}

}  // namespace
}  // namespace statebench
