#include "estimator/gnss_error_state_factor.hpp"

#include <gtest/gtest.h>

#include <memory>

#include "core/error.hpp"
#include "core/random.hpp"
#include "core/so3.hpp"
#include "estimator/gnss_propagated_position_factor.hpp"
#include "estimator/so3_manifold.hpp"
#include "estimator/state_parameters.hpp"
#include "helix_trajectory.hpp"
#include "jacobian_check.hpp"

namespace statebench::est {
namespace {

using testing::HelixTrajectory;

std::vector<std::vector<double>> ErrorStateBlocks(const NavState& s, const Vec3& e) {
  const auto p = StateParameters::FromNavState(s);
  auto v = [](const auto& a) { return std::vector<double>(a.begin(), a.end()); };
  return {v(p.q_world_imu), v(p.p_world), v(p.v_world), v(p.bias), {e.x()}, {e.y()}, {e.z()}};
}

Vec3 Residual(const ceres::CostFunction& f, const std::vector<std::vector<double>>& blocks) {
  std::vector<const double*> ptrs;
  for (const auto& b : blocks) ptrs.push_back(b.data());
  Vec3 r;
  f.Evaluate(ptrs.data(), r.data(), nullptr);
  return r;
}

// A fix offset by a slowly varying receiver error e is explained by the error state: zero
// residual at the truth with e, the whitened e without it; Jacobians against numeric
// differences, the error's columns S.
TEST(GnssErrorStateFactor, AddsTheReceiverErrorToThePredictedAntenna) {
  const HelixTrajectory helix;
  const auto samples = testing::HelixSamples(Vec3::Zero(), Vec3::Zero());
  const TimeNs t_i = FromSeconds(1.2), t_fix = FromSeconds(1.2534);
  const Vec3 lever(0.8, 0.3, 1.5);
  const Vec3 e(0.4, -0.7, 1.1);
  const NavState at_fix = helix.State(t_fix);
  const Vec3 z = at_fix.p_world + at_fix.q_world_imu * lever + e;
  const Mat3 covariance = Vec3(0.25, 0.36, 1.0).asDiagonal();
  const NavState state_i = helix.State(t_i);
  auto base = std::make_unique<GnssPropagatedPositionFactor>(
      z, covariance, lever,
      ImuPreintegration::FromSamples(samples, t_i, t_fix, ImuNoise{}, ImuBias{}),
      state_i.q_world_imu);
  const Mat3 S = base->sqrt_information();
  const GnssErrorStateFactor f(std::move(base), S);
  ASSERT_EQ(f.parameter_block_sizes().size(), 7u);
  EXPECT_LT(Residual(f, ErrorStateBlocks(state_i, e)).norm(), 1e-4);
  EXPECT_NEAR((Residual(f, ErrorStateBlocks(state_i, Vec3::Zero())) + S * e).norm(), 0.0, 1e-4);

  const RightQuaternionManifold q_manifold;
  auto rng = MakeRng(45, "gnss_error_state_jacobians");
  NormalSampler normal;
  const auto r3 = [&] { return Vec3(normal(rng), normal(rng), normal(rng)); };
  double worst = 0.0;
  for (int trial = 0; trial < 5; ++trial) {
    const auto check = testing::CheckJacobians(
        f, ErrorStateBlocks(testing::PerturbedState(state_i, r3), r3()),
        {&q_manifold, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr}, 1e-6);
    worst = std::max(worst, check.worst_relative_error);
  }
  std::printf("gnss error state factor: worst relative Jacobian error %.2e\n", worst);
  EXPECT_LT(worst, 1e-6);
}

TEST(GnssErrorStateFactor, RefusesAFactorWithoutThreeResiduals) {
  EXPECT_THROW(GnssErrorStateFactor(nullptr, Mat3::Identity()), InputError);
}

}  // namespace
}  // namespace statebench::est
