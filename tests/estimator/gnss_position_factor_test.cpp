#include "estimator/gnss_position_factor.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/random.hpp"
#include "core/so3.hpp"
#include "estimator/robust_kernel.hpp"
#include "estimator/so3_manifold.hpp"
#include "jacobian_check.hpp"

namespace statebench::est {
namespace {

const Vec3 kLeverArm(1.2, -0.4, 1.6);  // antenna in the IMU frame, m

TEST(GnssPositionFactor, ResidualIsWhitenedAntennaError) {
  const Quat q = so3::FromRollPitchYaw(0.05, -0.02, 2.0);
  const Vec3 p(10.0, -3.0, 1.0);
  const Vec3 antenna = p + q * kLeverArm;
  Mat3 cov = Mat3::Zero();
  cov.diagonal() << 0.02 * 0.02, 0.03 * 0.03, 0.05 * 0.05;
  const GnssPositionFactor at_truth(antenna, cov, kLeverArm);
  const GnssPositionFactor offset(antenna + Vec3(0.02, -0.06, 0.0), cov, kLeverArm);
  const double* params[] = {q.coeffs().data(), p.data()};
  Vec3 r;
  at_truth.Evaluate(params, r.data(), nullptr);
  EXPECT_LT(r.norm(), 1e-9);
  offset.Evaluate(params, r.data(), nullptr);
  EXPECT_NEAR(r.squaredNorm(), 1.0 + 4.0, 1e-9);  // 1 sigma east, 2 sigma north

  Mat3 bad = cov;
  bad(2, 2) = -1.0;
  EXPECT_THROW(GnssPositionFactor(antenna, bad, kLeverArm), InputError);
}

TEST(GnssPositionFactor, JacobiansMatchNumericDifferencesOnTheManifold) {
  const RightQuaternionManifold so3_manifold;
  auto rng = MakeRng(21, "gnss_factor_jacobians");
  NormalSampler normal;
  Mat3 cov;
  cov << 4e-4, 1e-4, 0, 1e-4, 9e-4, 2e-5, 0, 2e-5, 2.5e-3;
  double worst = 0.0;
  for (int trial = 0; trial < 10; ++trial) {
    const Quat q = so3::Exp<double>(Vec3(normal(rng), normal(rng), normal(rng)));
    const Vec3 p(normal(rng), normal(rng), normal(rng));
    const Vec3 z = p + 0.3 * Vec3(normal(rng), normal(rng), normal(rng));
    const GnssPositionFactor factor(z, cov, kLeverArm);
    const auto check = testing::CheckJacobians(
        factor, {{q.coeffs().data(), q.coeffs().data() + 4}, {p.data(), p.data() + 3}},
        {&so3_manifold, nullptr});
    worst = std::max(worst, check.worst_relative_error);
  }
  std::printf("gnss position factor: worst relative Jacobian error %.2e\n", worst);
  EXPECT_LT(worst, 1e-7);
}

TEST(RobustKernel, HuberAndCauchyDownweightLargeResidualsOnly) {
  EXPECT_EQ((RobustKernel{RobustKernelType::kNone, 1.0}.MakeLossFunction()), nullptr);
  for (auto type : {RobustKernelType::kHuber, RobustKernelType::kCauchy}) {
    const auto loss = RobustKernel{type, 3.0}.MakeLossFunction();
    ASSERT_NE(loss, nullptr);
    double rho_small[3], rho_large[3];
    loss->Evaluate(0.01, rho_small);  // squared norm
    loss->Evaluate(400.0, rho_large);
    EXPECT_NEAR(rho_small[0], 0.01, 1e-4);
    EXPECT_NEAR(rho_small[1], 1.0, 2e-3);  // Cauchy: 1 / (1 + s / a^2)
    EXPECT_LT(rho_large[0], 0.5 * 400.0);
    EXPECT_LT(rho_large[1], 0.2);
  }
  EXPECT_EQ(ParseRobustKernelType("cauchy"), RobustKernelType::kCauchy);
  EXPECT_THROW(ParseRobustKernelType("tukey"), InputError);
  EXPECT_THROW((RobustKernel{RobustKernelType::kHuber, 0.0}.MakeLossFunction()), InputError);
}

}  // namespace
}  // namespace statebench::est
