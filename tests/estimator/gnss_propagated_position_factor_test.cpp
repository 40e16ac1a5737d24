#include "estimator/gnss_propagated_position_factor.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "core/random.hpp"
#include "core/so3.hpp"
#include "estimator/gnss_position_factor.hpp"
#include "estimator/so3_manifold.hpp"
#include "estimator/state_parameters.hpp"
#include "helix_trajectory.hpp"
#include "jacobian_check.hpp"

namespace statebench::est {
namespace {

using testing::HelixTrajectory;

const Vec3 kPropagatedLever(0.8, 0.3, 1.5);

// 100 Hz samples of the helix over [0, 3] s, with a constant sensor bias added.
std::vector<ImuSample> BiasedSamples(const ImuBias& bias) {
  return testing::HelixSamples(bias.gyro, bias.accel);
}

std::vector<std::vector<double>> Blocks(const NavState& s) {
  const auto p = StateParameters::FromNavState(s);
  auto v = [](const auto& a) { return std::vector<double>(a.begin(), a.end()); };
  return {v(p.q_world_imu), v(p.p_world), v(p.v_world), v(p.bias)};
}

Vec3 UnwhitenedResidual(const GnssPropagatedPositionFactor& f, const NavState& s) {
  const auto blocks = Blocks(s);
  const double* ptrs[] = {blocks[0].data(), blocks[1].data(), blocks[2].data(), blocks[3].data()};
  Vec3 r;
  f.Evaluate(ptrs, r.data(), nullptr);
  const Eigen::LLT<Mat3> llt(f.effective_covariance());
  return llt.matrixL() * r;
}

// A fix taken 73.4 ms after state i (between IMU samples, keyframes 0.1 s apart) is predicted
// exactly at its own stamp; the closest state is 5 cm away at 10 m/s.
TEST(GnssPropagatedPositionFactor, PlacesTheFixAtItsOwnStamp) {
  const HelixTrajectory helix;
  const ImuBias bias{Vec3(0.004, -0.003, 0.002), Vec3(0.08, 0.05, -0.1)};
  const auto samples = BiasedSamples(bias);
  const TimeNs t_i = FromSeconds(1.2);
  const TimeNs t_fix = FromSeconds(1.2734);
  const NavState fix_truth = helix.State(t_fix);
  const Vec3 z = fix_truth.p_world + fix_truth.q_world_imu * kPropagatedLever;
  const Mat3 cov = 1e-4 * Mat3::Identity();

  NavState state_i = helix.State(t_i);
  state_i.gyro_bias = bias.gyro;
  state_i.accel_bias = bias.accel;
  // Linearised at a bias off by 10 %: the first-order correction takes up the difference.
  const ImuBias bias_lin{0.9 * bias.gyro, 0.9 * bias.accel};
  const GnssPropagatedPositionFactor factor(
      z, cov, kPropagatedLever, ImuPreintegration::FromSamples(samples, t_i, t_fix, ImuNoise{}, bias_lin),
      state_i.q_world_imu);
  const Vec3 r = UnwhitenedResidual(factor, state_i);
  std::printf("fix 73.4 ms after the state: propagated residual %.2e m\n", r.norm());
  EXPECT_LT(r.norm(), 1e-6);

  // Attaching the same fix to the closest state instead would be off by centimetres.
  const NavState closest = helix.State(FromSeconds(1.3));
  EXPECT_GT((closest.p_world + closest.q_world_imu * kPropagatedLever - z).norm(), 0.2);

  // The propagation adds its own uncertainty to the fix covariance.
  const Mat3 added = factor.effective_covariance() - cov;
  EXPECT_GT(added.trace(), 0.0);
  EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat3>(added).eigenvalues().minCoeff(), -1e-18);
  // Random-walk estimate: the gyro rotates the lever arm, trace 2 sg^2 tau |l|^2 (two axes
  // perpendicular to it on average), the accelerometer adds sa^2 tau^3 / 3 per axis.
  const ImuNoise noise;
  const double tau = ToSeconds(t_fix - t_i);
  const double expected = 2.0 * std::pow(noise.gyro_noise_density, 2) * tau * kPropagatedLever.squaredNorm() +
                          std::pow(noise.accel_noise_density, 2) * std::pow(tau, 3);
  std::printf("added covariance trace %.3e m^2, random-walk estimate %.3e m^2\n", added.trace(),
              expected);
  EXPECT_NEAR(added.trace(), expected, 0.15 * expected);
}

TEST(GnssPropagatedPositionFactor, ZeroPropagationEqualsUnaryFactor) {
  const HelixTrajectory helix;
  const auto samples = BiasedSamples(ImuBias{});
  const TimeNs t_i = FromSeconds(0.5);
  const Vec3 z(3.0, 19.0, 1.0);
  Mat3 cov;
  cov << 4e-4, 1e-4, 0, 1e-4, 9e-4, 0, 0, 0, 2.5e-3;
  const NavState s = helix.State(t_i);
  const GnssPropagatedPositionFactor propagated(
      z, cov, kPropagatedLever, ImuPreintegration::FromSamples(samples, t_i, t_i, ImuNoise{}, ImuBias{}),
      s.q_world_imu);
  const GnssPositionFactor unary(z, cov, kPropagatedLever);
  const auto blocks = Blocks(s);
  const double* ptrs[] = {blocks[0].data(), blocks[1].data(), blocks[2].data(), blocks[3].data()};
  Vec3 r_prop, r_unary;
  propagated.Evaluate(ptrs, r_prop.data(), nullptr);
  unary.Evaluate(ptrs, r_unary.data(), nullptr);
  EXPECT_LT((r_prop - r_unary).norm(), 1e-12);
}

TEST(GnssPropagatedPositionFactor, JacobiansMatchNumericDifferencesOnTheManifold) {
  const HelixTrajectory helix;
  const RightQuaternionManifold so3_manifold;
  auto rng = MakeRng(31, "gnss_propagated_jacobians");
  NormalSampler normal;
  const auto samples = BiasedSamples(ImuBias{});
  const auto r3 = [&] { return Vec3(normal(rng), normal(rng), normal(rng)); };
  double worst = 0.0;
  for (double tau : {0.004, 0.0734, 0.5}) {
    const TimeNs t_i = FromSeconds(1.0);
    const ImuBias bias_lin{Vec3(0.001, 0.0, -0.002), Vec3(0.0, 0.03, 0.0)};
    NavState s = helix.State(t_i);
    const GnssPropagatedPositionFactor factor(
        s.p_world + r3(), 1e-4 * Mat3::Identity(), kPropagatedLever,
        ImuPreintegration::FromSamples(samples, t_i, t_i + FromSeconds(tau), ImuNoise{}, bias_lin),
        s.q_world_imu);
    for (int trial = 0; trial < 5; ++trial) {
      const NavState x = testing::PerturbedState(s, r3);
      const auto check =
          testing::CheckJacobians(factor, Blocks(x), {&so3_manifold, nullptr, nullptr, nullptr},
                                  1e-6, trial == 0 ? "gnss propagated" : "");
      worst = std::max(worst, check.worst_relative_error);
    }
  }
  std::printf("gnss propagated factor: worst relative Jacobian error %.2e\n", worst);
  EXPECT_LT(worst, 1e-6);
}

}  // namespace
}  // namespace statebench::est
