#include "estimator/imu_factor.hpp"

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <memory>

#include "core/random.hpp"
#include "core/so3.hpp"
#include "estimator/so3_manifold.hpp"
#include "estimator/state_parameters.hpp"
#include "helix_trajectory.hpp"
#include "jacobian_check.hpp"

namespace statebench::est {
namespace {

using testing::HelixTrajectory;

ImuPreintegration HelixPreintegration(double t0_s, double duration_s, const ImuBias& bias_lin) {
  const HelixTrajectory helix;
  ImuPreintegration pim(ImuNoise{}, bias_lin);
  const int n = static_cast<int>(std::lround(duration_s * 100.0));
  for (int k = 0; k <= n; ++k) {
    const TimeNs t_ns = FromSeconds(t0_s) + k * 10 * kNsPerMillisecond;
    const double t = ToSeconds(t_ns);
    // Raw samples carry the linearisation bias so that the deltas stay those of the helix.
    pim.Integrate(t_ns, helix.Gyro(t) + bias_lin.gyro, helix.Accel(t) + bias_lin.accel);
  }
  return pim;
}

std::vector<std::vector<double>> Blocks(const NavState& si, const NavState& sj) {
  const auto pi = StateParameters::FromNavState(si);
  const auto pj = StateParameters::FromNavState(sj);
  auto v = [](const auto& a) { return std::vector<double>(a.begin(), a.end()); };
  return {v(pi.q_world_imu), v(pi.p_world), v(pi.v_world), v(pi.bias),
          v(pj.q_world_imu), v(pj.p_world), v(pj.v_world)};
}

NavState Perturbed(NavState s, std::mt19937_64& rng, NormalSampler& normal, double scale) {
  const auto r = [&] { return Vec3(normal(rng), normal(rng), normal(rng)); };
  s.q_world_imu = s.q_world_imu * so3::Exp<double>(0.05 * scale * r());
  s.p_world += 0.3 * scale * r();
  s.v_world += 0.2 * scale * r();
  s.gyro_bias += 0.01 * scale * r();
  s.accel_bias += 0.1 * scale * r();
  return s;
}

TEST(ImuFactor, ResidualVanishesAtTruth) {
  const HelixTrajectory helix;
  const ImuBias bias{Vec3(0.003, -0.002, 0.001), Vec3(0.05, -0.02, 0.03)};
  const ImuFactor factor(HelixPreintegration(1.0, 0.05, bias));
  NavState si = helix.State(FromSeconds(1.0));
  const NavState sj = helix.State(FromSeconds(1.05));
  si.gyro_bias = bias.gyro;
  si.accel_bias = bias.accel;
  const Vec9 r = factor.Residual(si, sj);
  std::printf("unwhitened residual at truth (50 ms, 100 Hz): %.2e\n", r.cwiseAbs().maxCoeff());
  EXPECT_LT(r.cwiseAbs().maxCoeff(), 1e-6);
  // A wrong state gives a large whitened residual.
  NavState wrong = sj;
  wrong.p_world.x() += 0.01;
  std::vector<const double*> ptrs;
  const auto blocks = Blocks(si, wrong);
  for (const auto& b : blocks) ptrs.push_back(b.data());
  Vec9 whitened;
  factor.Evaluate(ptrs.data(), whitened.data(), nullptr);
  EXPECT_GT(whitened.squaredNorm(), 100.0);
}

TEST(ImuFactor, AnalyticJacobiansMatchNumericDifferencesOnTheManifold) {
  const HelixTrajectory helix;
  const RightQuaternionManifold so3_manifold;
  const std::vector<const ceres::Manifold*> manifolds = {&so3_manifold, nullptr, nullptr, nullptr,
                                                         &so3_manifold, nullptr, nullptr};
  auto rng = MakeRng(3, "imu_factor_jacobians");
  NormalSampler normal;
  double worst = 0.0;
  for (double duration : {0.01, 0.1, 1.0}) {
    const ImuBias bias_lin{Vec3(0.002, 0.001, -0.003), Vec3(0.02, -0.05, 0.01)};
    const ImuFactor factor(HelixPreintegration(2.0, duration, bias_lin));
    for (int trial = 0; trial < 5; ++trial) {
      // Away from the truth so that r_R and the bias correction are not zero.
      const NavState si = Perturbed(helix.State(FromSeconds(2.0)), rng, normal, 1.0);
      const NavState sj = Perturbed(helix.State(FromSeconds(2.0 + duration)), rng, normal, 1.0);
      const auto check = testing::CheckJacobians(factor, Blocks(si, sj), manifolds, 1e-6,
                                                 trial == 0 ? "imu factor" : "");
      worst = std::max(worst, check.worst_relative_error);
      EXPECT_LT(check.worst_relative_error, 1e-6) << "duration " << duration;
    }
  }
  std::printf("imu factor: worst relative Jacobian error %.2e\n", worst);
}

TEST(ImuFactor, CeresGradientCheckerAgrees) {
  const HelixTrajectory helix;
  const RightQuaternionManifold so3_manifold;
  const std::vector<const ceres::Manifold*> manifolds = {&so3_manifold, nullptr, nullptr, nullptr,
                                                         &so3_manifold, nullptr, nullptr};
  const ImuFactor factor(HelixPreintegration(1.0, 0.2, ImuBias{}));
  auto rng = MakeRng(4, "imu_factor_gradient_checker");
  NormalSampler normal;
  const auto blocks = Blocks(Perturbed(helix.State(FromSeconds(1.0)), rng, normal, 1.0),
                             Perturbed(helix.State(FromSeconds(1.2)), rng, normal, 1.0));
  std::vector<const double*> ptrs;
  for (const auto& b : blocks) ptrs.push_back(b.data());
  ceres::NumericDiffOptions options;
  ceres::GradientChecker checker(&factor, &manifolds, options);
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE(checker.Probe(ptrs.data(), 1e-6, &results)) << results.error_log;
  std::printf("imu factor: GradientChecker max relative error %.2e\n",
              results.maximum_relative_error);
}

// Solving for state j with state i held constant recovers the truth (manifold + factor + Ceres).
TEST(ImuFactor, SolvesForTheNextState) {
  const HelixTrajectory helix;
  const ImuPreintegration pim = HelixPreintegration(1.0, 0.5, ImuBias{});
  const NavState truth_i = helix.State(FromSeconds(1.0));
  const NavState truth_j = helix.State(FromSeconds(1.5));
  auto si = StateParameters::FromNavState(truth_i);
  auto rng = MakeRng(5, "imu_factor_solve");
  NormalSampler normal;
  auto sj = StateParameters::FromNavState(Perturbed(truth_j, rng, normal, 2.0));

  ceres::Problem problem;
  problem.AddResidualBlock(new ImuFactor(pim), nullptr, si.q_world_imu.data(), si.p_world.data(),
                           si.v_world.data(), si.bias.data(), sj.q_world_imu.data(),
                           sj.p_world.data(), sj.v_world.data());
  problem.SetManifold(si.q_world_imu.data(), new RightQuaternionManifold);
  problem.SetManifold(sj.q_world_imu.data(), new RightQuaternionManifold);
  for (double* block :
       {si.q_world_imu.data(), si.p_world.data(), si.v_world.data(), si.bias.data()}) {
    problem.SetParameterBlockConstant(block);
  }
  ceres::Solver::Options options;
  options.max_num_iterations = 20;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  EXPECT_LE(summary.iterations.size(), 8u) << summary.BriefReport();
  // The optimum is the IMU prediction; it differs from the truth only by the 0.5 s
  // discretisation error of the preintegration (~2e-6).
  const NavState est = sj.ToNavState(truth_j.t_ns);
  const NavState predicted = pim.Predict(truth_i);
  EXPECT_LT(so3::Log<double>(predicted.q_world_imu.conjugate() * est.q_world_imu).norm(), 1e-9);
  EXPECT_LT((est.v_world - predicted.v_world).norm(), 1e-9);
  EXPECT_LT((est.p_world - predicted.p_world).norm(), 1e-9);
  EXPECT_LT(so3::Log<double>(truth_j.q_world_imu.conjugate() * est.q_world_imu).norm(), 5e-6);
  EXPECT_LT((est.v_world - truth_j.v_world).norm(), 1e-5);
  EXPECT_LT((est.p_world - truth_j.p_world).norm(), 1e-5);
}

}  // namespace
}  // namespace statebench::est
