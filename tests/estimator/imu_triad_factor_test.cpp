#include "estimator/imu_triad_factor.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "core/error.hpp"
#include "core/random.hpp"
#include "core/so3.hpp"
#include "estimator/so3_manifold.hpp"
#include "estimator/state_parameters.hpp"
#include "helix_trajectory.hpp"
#include "jacobian_check.hpp"

namespace statebench::est {
namespace {

using testing::HelixTrajectory;
using Triad = ImuTriadTerm::Triad;

// The helix measured by a triad y = (I + K) u + b (K_g on the gyro, K_a on the accelerometer).
ImuPreintegration MeasuredHelix(double t0_s, double duration_s, const ImuBias& bias,
                                const Mat3& K_g, const Mat3& K_a) {
  const HelixTrajectory helix;
  ImuPreintegration pim(ImuNoise{}, bias);
  const int n = static_cast<int>(std::lround(duration_s * 100.0));
  for (int k = 0; k <= n; ++k) {
    const TimeNs t_ns = FromSeconds(t0_s) + k * 10 * kNsPerMillisecond;
    const double t = ToSeconds(t_ns);
    pim.Integrate(t_ns, (Mat3::Identity() + K_g) * helix.Gyro(t) + bias.gyro,
                  (Mat3::Identity() + K_a) * helix.Accel(t) + bias.accel);
  }
  return pim;
}

std::vector<std::vector<double>> Blocks(const NavState& si, const NavState& sj,
                                        const std::vector<double>& terms) {
  const auto pi = StateParameters::FromNavState(si);
  const auto pj = StateParameters::FromNavState(sj);
  auto v = [](const auto& a) { return std::vector<double>(a.begin(), a.end()); };
  std::vector<std::vector<double>> out = {v(pi.q_world_imu), v(pi.p_world),     v(pi.v_world),
                                          v(pi.bias),        v(pj.q_world_imu), v(pj.p_world),
                                          v(pj.v_world)};
  for (double t : terms) out.push_back({t});
  return out;
}

std::vector<ImuTriadTerm> BothTriads() {
  std::vector<ImuTriadTerm> terms = AllTriadTerms(Triad::kGyro);
  for (const ImuTriadTerm& t : AllTriadTerms(Triad::kAccel)) terms.push_back(t);
  return terms;
}

// The terms' values in AllTriadTerms order read from K_g and K_a.
std::vector<double> TermValues(const std::vector<ImuTriadTerm>& terms, const Mat3& K_g,
                               const Mat3& K_a) {
  std::vector<double> out;
  for (const ImuTriadTerm& t : terms) {
    out.push_back((t.triad == Triad::kGyro ? K_g : K_a)(t.row, t.col));
  }
  return out;
}

Vec9 Evaluate(const ceres::CostFunction& f, const std::vector<std::vector<double>>& blocks) {
  std::vector<const double*> ptrs;
  for (const auto& b : blocks) ptrs.push_back(b.data());
  Vec9 r;
  EXPECT_TRUE(f.Evaluate(ptrs.data(), r.data(), nullptr));
  return r;
}

Mat3 RandomTriad(std::mt19937_64& rng, NormalSampler& normal, double sigma) {
  Mat3 K;
  for (int i = 0; i < 9; ++i) K(i / 3, i % 3) = sigma * normal(rng);
  return K;
}

TEST(ImuTriadFactor, NamesEveryEntryOnceScalesFirst) {
  const std::vector<ImuTriadTerm> terms = AllTriadTerms(Triad::kAccel);
  ASSERT_EQ(terms.size(), 9u);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_EQ(terms[axis].row, axis);
    EXPECT_EQ(terms[axis].col, axis);
  }
  int seen = 0;
  for (const ImuTriadTerm& t : terms) {
    EXPECT_EQ(t.triad, Triad::kAccel);
    seen |= 1 << (3 * t.row + t.col);
  }
  EXPECT_EQ(seen, 511);
  EXPECT_THROW(ImuTriadFactor(MeasuredHelix(1.0, 0.1, ImuBias{}, Mat3::Zero(), Mat3::Zero()),
                              {{Triad::kGyro, 3, 0}}),
               InputError);
}

TEST(ImuTriadFactor, WithZeroTermsIsTheImuFactor) {
  const HelixTrajectory helix;
  const ImuBias bias{Vec3(0.002, -0.001, 0.003), Vec3(0.03, 0.01, -0.02)};
  const ImuPreintegration pim = MeasuredHelix(1.0, 0.1, bias, Mat3::Zero(), Mat3::Zero());
  const ImuFactor plain(pim);
  const ImuTriadFactor triad(pim, BothTriads());
  const NavState si = helix.State(FromSeconds(1.0));
  NavState sj = helix.State(FromSeconds(1.1));
  sj.p_world.x() += 0.02;
  const auto blocks = Blocks(si, sj, std::vector<double>(18, 0.0));
  const std::vector<std::vector<double>> plain_blocks(blocks.begin(), blocks.begin() + 7);
  EXPECT_EQ(Evaluate(plain, plain_blocks), Evaluate(triad, blocks));
}

// The factor's whole point: a triad with scale and cross-axis errors explains its samples once
// the factor is given those errors; without them the residual is the errors' effect.
TEST(ImuTriadFactor, TheTrueTriadErrorsExplainTheSamples) {
  const HelixTrajectory helix;
  auto rng = MakeRng(11, "imu_triad_truth");
  NormalSampler normal;
  const Mat3 K_g = RandomTriad(rng, normal, 3e-3);
  const Mat3 K_a = RandomTriad(rng, normal, 3e-3);
  const ImuBias bias{Vec3(0.002, -0.001, 0.003), Vec3(0.03, 0.01, -0.02)};
  const std::vector<ImuTriadTerm> terms = BothTriads();
  for (double duration : {0.1, 0.5}) {
    const ImuTriadFactor factor(MeasuredHelix(3.0, duration, bias, K_g, K_a), terms);
    NavState si = helix.State(FromSeconds(3.0));
    si.gyro_bias = bias.gyro;
    si.accel_bias = bias.accel;
    const NavState sj = helix.State(FromSeconds(3.0 + duration));
    const double with = Evaluate(factor, Blocks(si, sj, TermValues(terms, K_g, K_a))).norm();
    const double without = Evaluate(factor, Blocks(si, sj, std::vector<double>(18, 0.0))).norm();
    std::printf("%.1f s: whitened residual %.3g with the true triad errors, %.3g without\n",
                duration, with, without);
    // Left: the second-order part K (y - y_bar), K^2 and the preintegration's own error.
    EXPECT_LT(with, 0.05 * without) << duration;
  }
}

TEST(ImuTriadFactor, AnalyticJacobiansMatchNumericDifferencesOnTheManifold) {
  const HelixTrajectory helix;
  const RightQuaternionManifold so3_manifold;
  std::vector<const ceres::Manifold*> manifolds = {&so3_manifold, nullptr, nullptr, nullptr,
                                                   &so3_manifold, nullptr, nullptr};
  manifolds.insert(manifolds.end(), 18, nullptr);
  auto rng = MakeRng(12, "imu_triad_jacobians");
  NormalSampler normal;
  double worst = 0.0;
  const ImuBias bias_lin{Vec3(0.002, 0.001, -0.003), Vec3(0.02, -0.05, 0.01)};
  for (double duration : {0.01, 0.1, 1.0}) {
    const ImuTriadFactor factor(
        MeasuredHelix(2.0, duration, bias_lin, RandomTriad(rng, normal, 2e-3),
                      RandomTriad(rng, normal, 2e-3)),
        BothTriads());
    for (int trial = 0; trial < 4; ++trial) {
      NavState si = helix.State(FromSeconds(2.0));
      si.q_world_imu = si.q_world_imu * so3::Exp<double>(Vec3(0.03, -0.02, 0.04));
      si.v_world += Vec3(0.1 * normal(rng), 0.1 * normal(rng), 0.1 * normal(rng));
      si.gyro_bias = Vec3(0.01 * normal(rng), 0.01 * normal(rng), 0.01 * normal(rng));
      si.accel_bias = Vec3(0.1 * normal(rng), 0.1 * normal(rng), 0.1 * normal(rng));
      NavState sj = helix.State(FromSeconds(2.0 + duration));
      sj.p_world += Vec3(0.2 * normal(rng), 0.2 * normal(rng), 0.2 * normal(rng));
      std::vector<double> terms(18);
      for (double& t : terms) t = 0.005 * normal(rng);
      // A step of 1e-5: the triad blocks' entries are 3-4 orders below the residual's, so 1e-6
      // leaves them with ~1e-6 of rounding from the differences (central differences: h^2 error).
      const auto check = testing::CheckJacobians(factor, Blocks(si, sj, terms), manifolds, 1e-5,
                                                 trial == 0 ? "imu triad factor" : "");
      worst = std::max(worst, check.worst_relative_error);
      EXPECT_LT(check.worst_relative_error, 1e-6) << "duration " << duration;
    }
  }
  std::printf("imu triad factor: worst relative Jacobian error %.2e\n", worst);
}

}  // namespace
}  // namespace statebench::est
