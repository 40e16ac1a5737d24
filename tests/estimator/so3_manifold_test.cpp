#include "estimator/so3_manifold.hpp"

#include <gtest/gtest.h>

#include "core/random.hpp"
#include "core/so3.hpp"

namespace statebench::est {
namespace {

Quat RandomRotation(std::mt19937_64& rng, NormalSampler& normal, double scale) {
  return so3::Exp<double>(scale * Vec3(normal(rng), normal(rng), normal(rng)));
}

Vec3 QuatDistance(const Quat& a, const Quat& b) { return so3::Log<double>(a.conjugate() * b); }

TEST(RightQuaternionManifold, PlusMinusInvariants) {
  const RightQuaternionManifold manifold;
  EXPECT_EQ(manifold.AmbientSize(), 4);
  EXPECT_EQ(manifold.TangentSize(), 3);
  auto rng = MakeRng(7, "so3_manifold");
  NormalSampler normal;
  for (int trial = 0; trial < 200; ++trial) {
    const Quat x = RandomRotation(rng, normal, 1.5);
    const Quat y = RandomRotation(rng, normal, 1.5);
    const Vec3 d = 0.8 * Vec3(normal(rng), normal(rng), normal(rng)) / 1.7;
    if (d.norm() >= 3.0) continue;  // Minus(Plus(x, d), x) = d needs |d| < pi

    Quat out;
    const Vec3 zero_delta = Vec3::Zero();
    manifold.Plus(x.coeffs().data(), zero_delta.data(), out.coeffs().data());
    EXPECT_LT(QuatDistance(x, out).norm(), 1e-15);  // Plus(x, 0) = x

    Vec3 zero;
    manifold.Minus(x.coeffs().data(), x.coeffs().data(), zero.data());
    EXPECT_LT(zero.norm(), 1e-15);  // Minus(x, x) = 0

    Quat x_plus_d;
    manifold.Plus(x.coeffs().data(), d.data(), x_plus_d.coeffs().data());
    EXPECT_NEAR(x_plus_d.norm(), 1.0, 1e-15);
    // Right perturbation: Plus(x, d) = x Exp(d).
    EXPECT_LT(QuatDistance(x * so3::Exp<double>(d), x_plus_d).norm(), 1e-14);
    Vec3 d_back;
    manifold.Minus(x_plus_d.coeffs().data(), x.coeffs().data(), d_back.data());
    EXPECT_LT((d_back - d).norm(), 1e-12);  // Minus(Plus(x, d), x) = d

    Vec3 y_minus_x;
    manifold.Minus(y.coeffs().data(), x.coeffs().data(), y_minus_x.data());
    Quat y_back;
    manifold.Plus(x.coeffs().data(), y_minus_x.data(), y_back.coeffs().data());
    EXPECT_LT(QuatDistance(y, y_back).norm(), 1e-12);  // Plus(x, Minus(y, x)) = y
  }
}

TEST(RightQuaternionManifold, JacobiansMatchNumericDifferencesAndInvertEachOther) {
  const RightQuaternionManifold manifold;
  auto rng = MakeRng(8, "so3_manifold_jacobians");
  NormalSampler normal;
  const double h = 1e-6;
  for (int trial = 0; trial < 20; ++trial) {
    const Quat x = RandomRotation(rng, normal, 1.5);
    Mat43 plus_jacobian;
    Mat34 minus_jacobian;
    manifold.PlusJacobian(x.coeffs().data(), plus_jacobian.data());
    manifold.MinusJacobian(x.coeffs().data(), minus_jacobian.data());
    Mat43 plus_numeric;
    for (int k = 0; k < 3; ++k) {
      Vec3 d = Vec3::Zero();
      d(k) = h;
      Quat a, b;
      manifold.Plus(x.coeffs().data(), d.data(), a.coeffs().data());
      const Vec3 minus_d = -d;
      manifold.Plus(x.coeffs().data(), minus_d.data(), b.coeffs().data());
      plus_numeric.col(k) = (a.coeffs() - b.coeffs()) / (2 * h);
    }
    EXPECT_LT((plus_jacobian - plus_numeric).cwiseAbs().maxCoeff(), 1e-9);
    Mat34 minus_numeric;
    for (int k = 0; k < 4; ++k) {
      Vec4 a = x.coeffs(), b = x.coeffs();
      a(k) += h;
      b(k) -= h;
      Vec3 ma, mb;
      manifold.Minus(a.data(), x.coeffs().data(), ma.data());
      manifold.Minus(b.data(), x.coeffs().data(), mb.data());
      minus_numeric.col(k) = (ma - mb) / (2 * h);
    }
    EXPECT_LT((minus_jacobian - minus_numeric).cwiseAbs().maxCoeff(), 1e-8);
    EXPECT_LT((minus_jacobian * plus_jacobian - Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-14);
  }
}

}  // namespace
}  // namespace statebench::est
