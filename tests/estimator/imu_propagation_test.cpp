#include "estimator/imu_propagation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "core/so3.hpp"
#include "helix_trajectory.hpp"

namespace statebench::est {
namespace {

using testing::HelixTrajectory;

// x [+] d in the core/state.hpp ordering (right rotation perturbation, additive elsewhere).
NavState Plus(const NavState& x, const Vec15& d) {
  NavState y = x;
  y.q_world_imu = (x.q_world_imu * so3::Exp<double>(d.segment<3>(kRotationIndex))).normalized();
  y.p_world += d.segment<3>(kPositionIndex);
  y.v_world += d.segment<3>(kVelocityIndex);
  y.gyro_bias += d.segment<3>(kGyroBiasIndex);
  y.accel_bias += d.segment<3>(kAccelBiasIndex);
  return y;
}

Vec15 Minus(const NavState& y, const NavState& x) {
  Vec15 d;
  d << so3::Log<double>(x.q_world_imu.conjugate() * y.q_world_imu), y.p_world - x.p_world,
      y.v_world - x.v_world, y.gyro_bias - x.gyro_bias, y.accel_bias - x.accel_bias;
  return d;
}

struct Fixture {
  NavState start;
  ImuPreintegration pim{ImuNoise{}, ImuBias{}};
  Fixture() {
    const HelixTrajectory helix;
    start = helix.State(FromSeconds(1.0));
    start.gyro_bias = Vec3(1e-3, -2e-3, 5e-4);
    start.accel_bias = Vec3(0.05, -0.02, 0.03);
    pim = ImuPreintegration(ImuNoise{}, ImuBias{start.gyro_bias, start.accel_bias});
    for (int k = 0; k <= 50; ++k) {
      const double t = 1.0 + 0.01 * k;
      pim.Integrate(FromSeconds(t), helix.Gyro(t), helix.Accel(t));
    }
  }
};

TEST(ImuPropagation, JacobianMatchesNumericDifferencesOnTheManifold) {
  const Fixture f;
  const Mat15 F = PropagationJacobian(f.start, f.pim);
  const NavState end = f.pim.Predict(f.start);
  Mat15 F_num;
  const double h = 1e-6;
  for (int i = 0; i < 15; ++i) {
    const Vec15 d = h * Vec15::Unit(i);
    const NavState plus = Plus(f.start, d);
    const NavState minus = Plus(f.start, -d);
    // Exact re-integration with the perturbed bias, not the first-order correction.
    const ImuBias b_plus{plus.gyro_bias, plus.accel_bias};
    const ImuBias b_minus{minus.gyro_bias, minus.accel_bias};
    F_num.col(i) = (Minus(f.pim.Reintegrated(b_plus).Predict(plus), end) -
                    Minus(f.pim.Reintegrated(b_minus).Predict(minus), end)) /
                   (2 * h);
  }
  std::printf("propagation Jacobian vs numeric: max difference %.2e (largest entry %.2e)\n",
              (F - F_num).cwiseAbs().maxCoeff(), F.cwiseAbs().maxCoeff());
  EXPECT_LT((F - F_num).cwiseAbs().maxCoeff(), 1e-6) << "F\n" << F << "\nnumeric\n" << F_num;
}

TEST(ImuPropagation, CovarianceAddsThePreintegrationNoiseInTheWorldFrame) {
  const Fixture f;
  const PropagatedState p = Propagate(f.start, Mat15::Zero(), f.pim);
  const Mat3 R = f.start.q_world_imu.toRotationMatrix();
  const Mat9& Q = f.pim.covariance();
  EXPECT_TRUE(p.covariance.isApprox(p.covariance.transpose(), 1e-15));
  const auto block = [](const auto& M, int i, int j) { return Mat3(M.template block<3, 3>(i, j)); };
  const Mat15& P = p.covariance;
  EXPECT_TRUE(block(P, kRotationIndex, kRotationIndex)
                  .isApprox(block(Q, kPreintRotation, kPreintRotation), 1e-12));
  EXPECT_TRUE(block(P, kPositionIndex, kPositionIndex)
                  .isApprox(R * block(Q, kPreintPosition, kPreintPosition) * R.transpose(), 1e-12));
  EXPECT_TRUE(block(P, kVelocityIndex, kPositionIndex)
                  .isApprox(R * block(Q, kPreintVelocity, kPreintPosition) * R.transpose(), 1e-12));
  const ImuNoise n;
  EXPECT_NEAR(p.covariance(kGyroBiasIndex, kGyroBiasIndex),
              n.gyro_random_walk * n.gyro_random_walk * 0.5, 1e-20);
  EXPECT_NEAR(p.covariance(kAccelBiasIndex, kAccelBiasIndex),
              n.accel_random_walk * n.accel_random_walk * 0.5, 1e-15);
  // A prior covariance is carried by F.
  Mat15 P0 = Mat15::Identity() * 1e-4;
  const Mat15 F = PropagationJacobian(f.start, f.pim);
  const PropagatedState q = Propagate(f.start, P0, f.pim);
  EXPECT_TRUE((q.covariance - p.covariance).isApprox(F * P0 * F.transpose(), 1e-10));
  EXPECT_EQ(q.state.t_ns, f.pim.end_ns());
}

// The standstill test's shortcut computes the velocity block alone; it must be Propagate's block
// bit for bit (a full, correlated covariance, and the empty interval).
TEST(ImuPropagation, VelocityAloneIsPropagatesVelocityBlockBitForBit) {
  const Fixture f;
  Mat15 A;
  for (int r = 0; r < 15; ++r) {
    for (int c = 0; c < 15; ++c) A(r, c) = std::sin(1.0 + r + 0.37 * c * c);
  }
  const Mat15 P0 = 1e-3 * (A * A.transpose() + Mat15::Identity());
  const Mat15 P0_rounded = 0.5 * (P0 + P0.transpose());
  for (const ImuPreintegration& pim : {f.pim, ImuPreintegration(ImuNoise{}, ImuBias{})}) {
    const PropagatedState full = Propagate(f.start, P0_rounded, pim);
    const PropagatedVelocity v = PropagateVelocity(f.start, P0_rounded, pim);
    const Mat3 expected = full.covariance.block<3, 3>(kVelocityIndex, kVelocityIndex);
    EXPECT_EQ(std::memcmp(v.velocity_covariance.data(), expected.data(), sizeof(Mat3)), 0)
        << v.velocity_covariance << "\nvs\n" << expected;
    EXPECT_EQ(std::memcmp(v.state.v_world.data(), full.state.v_world.data(), sizeof(Vec3)), 0);
    EXPECT_EQ(v.state.t_ns, full.state.t_ns);
  }
}

}  // namespace
}  // namespace statebench::est
