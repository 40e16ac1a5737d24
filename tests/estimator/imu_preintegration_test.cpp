#include "estimator/imu_preintegration.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <span>
#include <vector>

#include "core/error.hpp"
#include "core/random.hpp"
#include "core/so3.hpp"
#include "helix_trajectory.hpp"

namespace statebench::est {
namespace {

using testing::HelixTrajectory;

using testing::DeltaErrors;

// Noise-free samples of the helix at rate_hz covering [t0, t0 + duration], starting `context`
// samples before t0.
std::vector<ImuSample> HelixSamples(double t0_s, double duration_s, double rate_hz,
                                    int context = 0) {
  const HelixTrajectory helix;
  const TimeNs step_ns = FromSeconds(1.0 / rate_hz);
  const TimeNs t0_ns = FromSeconds(t0_s);
  const int n = static_cast<int>(std::lround(duration_s * rate_hz));
  std::vector<ImuSample> samples;
  for (int k = -context; k <= n; ++k) {
    samples.push_back(testing::SampleOf(helix, t0_ns + k * step_ns));
  }
  return samples;
}

// Difference between the preintegrated deltas and the exact deltas of the truth states.
DeltaErrors CompareWithTruth(const ImuPreintegration& pim) {
  return testing::PreintegrationErrors(HelixTrajectory{}, pim);
}

// Over [t0, t0 + duration]: from a buffer holding 3 earlier samples (cubic interpolation from
// the first step), or streamed sample by sample from t0 (no earlier samples: the first step is
// linear, the second quadratic).
DeltaErrors NoiseFreeError(double t0_s, double duration_s, double rate_hz, bool streamed) {
  const int context = streamed ? 0 : 3;
  const auto samples = HelixSamples(t0_s, duration_s, rate_hz, context);
  ImuPreintegration pim(ImuNoise{}, ImuBias{});
  if (streamed) {
    for (const auto& s : samples) pim.Integrate(s);
  } else {
    pim = ImuPreintegration::FromSamples(samples, FromSeconds(t0_s), samples.back().header.stamp_ns,
                                         ImuNoise{}, ImuBias{});
  }
  const DeltaErrors e = CompareWithTruth(pim);
  std::printf("noise-free %5.0f Hz over %.2f s%s: rot %.2e rad, vel %.2e m/s, pos %.2e m\n",
              rate_hz, duration_s, streamed ? " (streamed)" : "", e.rotation, e.velocity,
              e.position);
  return e;
}

TEST(HelixTrajectory, GyroMatchesFiniteDifferenceOfAttitude) {
  const HelixTrajectory helix;
  for (double t : {0.3, 1.7, 4.2}) {
    const double h = 1e-5;
    const Vec3 w_num =
        so3::Log<double>(helix.Orientation(t - h).conjugate() * helix.Orientation(t + h)) / (2 * h);
    EXPECT_LT((w_num - helix.Gyro(t)).norm(), 1e-8);
    const Vec3 a_num = (helix.Velocity(t + h) - helix.Velocity(t - h)) / (2 * h);
    EXPECT_LT((a_num - helix.Acceleration(t)).norm(), 1e-7);
    const Vec3 v_num = (helix.Position(t + h) - helix.Position(t - h)) / (2 * h);
    EXPECT_LT((v_num - helix.Velocity(t)).norm(), 1e-7);
  }
}

// Fourth-order scheme (see the header; tests/estimator/imu_preintegration_accuracy_test.cpp for
// a car-like motion). Largest error measured on this helix with earlier samples as context:
// 100 Hz over 10 ms 4.3e-12, over 0.1 s 4.7e-11, over 1 s 4.7e-10; 200 Hz over 1 s 2.9e-11
// (the former trapezoidal scheme: 1.1e-7, 1.05e-6, 1.3e-5, 3.3e-6). Streamed from the first
// sample, the linear first step adds up to 1e-7 (2.0e-7 over 1 s: third order overall).
TEST(ImuPreintegration, NoiseFreeDataReproducesTruthDeltas) {
  for (const bool streamed : {false, true}) {
    EXPECT_LT(NoiseFreeError(1.0, 0.01, 100.0, streamed).Max(), 1e-6);
    EXPECT_LT(NoiseFreeError(1.0, 0.1, 100.0, streamed).Max(), 1e-6);
    EXPECT_LT(NoiseFreeError(1.0, 1.0, 100.0, streamed).Max(), 1e-6);
  }
  // Halving the step divides the error by ~16 (fourth order) with context, by ~8 when streamed
  // from the first sample (the linear first step has a local error O(h^3)).
  const DeltaErrors e100 = NoiseFreeError(1.0, 1.0, 100.0, false);
  const DeltaErrors e200 = NoiseFreeError(1.0, 1.0, 200.0, false);
  EXPECT_LT(e100.Max(), 1e-8);
  EXPECT_NEAR(e100.rotation / e200.rotation, 16.0, 2.0);
  EXPECT_NEAR(e100.velocity / e200.velocity, 16.0, 2.0);
  EXPECT_NEAR(e100.position / e200.position, 16.0, 2.0);
  const DeltaErrors s100 = NoiseFreeError(1.0, 1.0, 100.0, true);
  const DeltaErrors s200 = NoiseFreeError(1.0, 1.0, 200.0, true);
  EXPECT_NEAR(s100.velocity / s200.velocity, 8.0, 1.5);
}

TEST(ImuPreintegration, PredictReproducesTruthState) {
  const HelixTrajectory helix;
  const auto samples = HelixSamples(2.0, 0.05, 100.0);
  ImuPreintegration pim(ImuNoise{}, ImuBias{});
  for (const auto& s : samples) pim.Integrate(s);
  const NavState predicted = pim.Predict(helix.State(samples.front().header.stamp_ns));
  const NavState truth = helix.State(samples.back().header.stamp_ns);
  EXPECT_EQ(predicted.t_ns, truth.t_ns);
  EXPECT_LT(so3::Log<double>(truth.q_world_imu.conjugate() * predicted.q_world_imu).norm(), 1e-6);
  EXPECT_LT((predicted.v_world - truth.v_world).norm(), 1e-6);
  EXPECT_LT((predicted.p_world - truth.p_world).norm(), 1e-6);
}

// States at arbitrary stamps between samples: interpolated boundary samples.
TEST(ImuPreintegration, IntervalBetweenSamplesUsesInterpolatedBoundaries) {
  const auto samples = HelixSamples(1.0, 1.0, 100.0);
  const TimeNs t_a = FromSeconds(1.2345678);
  const TimeNs t_b = FromSeconds(1.3012345);
  const TimeNs t_c = FromSeconds(1.3398765);
  const auto ab = ImuPreintegration::FromSamples(samples, t_a, t_b, ImuNoise{}, ImuBias{});
  EXPECT_EQ(ab.start_ns(), t_a);
  EXPECT_EQ(ab.end_ns(), t_b);
  EXPECT_EQ(ab.num_steps(), 8);  // 1.2345678 -> 1.24 ... 1.30 -> 1.3012345
  const DeltaErrors e = CompareWithTruth(ab);
  std::printf("off-grid interval 66.7 ms at 100 Hz: rot %.2e, vel %.2e, pos %.2e\n", e.rotation,
              e.velocity, e.position);
  EXPECT_LT(e.Max(), 1e-6);

  // Both boundaries inside one sample gap.
  const TimeNs t_d = FromSeconds(1.5012);
  const TimeNs t_e = FromSeconds(1.5087);
  const auto de = ImuPreintegration::FromSamples(samples, t_d, t_e, ImuNoise{}, ImuBias{});
  EXPECT_EQ(de.num_steps(), 1);
  EXPECT_LT(CompareWithTruth(de).Max(), 1e-6);

  // Splitting an interval at an interpolated stamp and composing the halves gives the whole.
  const auto bc = ImuPreintegration::FromSamples(samples, t_b, t_c, ImuNoise{}, ImuBias{});
  const auto ac = ImuPreintegration::FromSamples(samples, t_a, t_c, ImuNoise{}, ImuBias{});
  const Quat dq = ab.delta_q() * bc.delta_q();
  const Vec3 dv = ab.delta_v() + ab.delta_q() * bc.delta_v();
  const Vec3 dp = ab.delta_p() + ab.delta_v() * bc.dt() + ab.delta_q() * bc.delta_p();
  EXPECT_NEAR(ac.dt(), ab.dt() + bc.dt(), 1e-12);
  EXPECT_LT(so3::Log<double>(ac.delta_q().conjugate() * dq).norm(), 1e-8);
  EXPECT_LT((ac.delta_v() - dv).norm(), 1e-7);
  EXPECT_LT((ac.delta_p() - dp).norm(), 1e-8);

  EXPECT_THROW(
      ImuPreintegration::FromSamples(samples, FromSeconds(0.9), t_b, ImuNoise{}, ImuBias{}),
      InputError);
}

TEST(ImuPreintegration, BiasJacobiansMatchCentralDifferencesOfReintegration) {
  const auto samples = HelixSamples(3.0, 0.5, 100.0);
  const ImuBias bias_lin{Vec3(0.01, -0.02, 0.005), Vec3(0.1, 0.05, -0.2)};
  const auto pim =
      ImuPreintegration::FromSamples(samples, samples.front().header.stamp_ns,
                                     samples.back().header.stamp_ns, ImuNoise{}, bias_lin);
  Eigen::Matrix<double, 9, 6> J_num;
  const double eps = 1e-6;
  for (int c = 0; c < 6; ++c) {
    Vec6 db = Vec6::Zero();
    db(c) = eps;
    const auto plus = pim.Reintegrated(ImuBias::FromVector(bias_lin.AsVector() + db));
    const auto minus = pim.Reintegrated(ImuBias::FromVector(bias_lin.AsVector() - db));
    J_num.block<3, 1>(kPreintRotation, c) =
        (so3::Log<double>(pim.delta_q().conjugate() * plus.delta_q()) -
         so3::Log<double>(pim.delta_q().conjugate() * minus.delta_q())) /
        (2 * eps);
    J_num.block<3, 1>(kPreintVelocity, c) = (plus.delta_v() - minus.delta_v()) / (2 * eps);
    J_num.block<3, 1>(kPreintPosition, c) = (plus.delta_p() - minus.delta_p()) / (2 * eps);
  }
  Eigen::Matrix<double, 9, 6> J = Eigen::Matrix<double, 9, 6>::Zero();
  J.block<3, 3>(kPreintRotation, 0) = pim.d_R_d_bg();
  J.block<3, 3>(kPreintVelocity, 0) = pim.d_v_d_bg();
  J.block<3, 3>(kPreintVelocity, 3) = pim.d_v_d_ba();
  J.block<3, 3>(kPreintPosition, 0) = pim.d_p_d_bg();
  J.block<3, 3>(kPreintPosition, 3) = pim.d_p_d_ba();
  const double err = (J - J_num).cwiseAbs().maxCoeff();
  std::printf("bias Jacobian max abs error %.2e (max entry %.2e)\n", err, J.cwiseAbs().maxCoeff());
  EXPECT_LT(err, 1e-7);
}

// The first-order corrected deltas differ from a re-integration by a term quadratic in the
// bias change: halving the change divides the error by 4.
TEST(ImuPreintegration, BiasCorrectionIsFirstOrderAccurate) {
  const auto samples = HelixSamples(3.0, 1.0, 100.0);
  const ImuPreintegration pim = [&] {
    ImuPreintegration p(ImuNoise{}, ImuBias{});
    for (const auto& s : samples) p.Integrate(s);
    return p;
  }();
  Vec6 direction;
  direction << 0.02, -0.01, 0.015, 0.2, 0.1, -0.15;  // rad/s, m/s^2
  double previous = 0.0;
  for (double scale : {1.0, 0.5, 0.25, 0.125}) {
    const ImuBias b = ImuBias::FromVector(scale * direction);
    const auto exact = pim.Reintegrated(b);
    const double e_rot =
        so3::Log<double>(exact.delta_q().conjugate() * pim.CorrectedDeltaQ(b)).norm();
    const double e_vel = (exact.delta_v() - pim.CorrectedDeltaV(b)).norm();
    const double e_pos = (exact.delta_p() - pim.CorrectedDeltaP(b)).norm();
    const double uncorrected = (exact.delta_p() - pim.delta_p()).norm();
    const double total = e_rot + e_vel + e_pos;
    std::printf(
        "bias scale %.3f: corrected err rot %.2e vel %.2e pos %.2e (uncorrected pos %.2e)\n", scale,
        e_rot, e_vel, e_pos, uncorrected);
    EXPECT_LT(e_pos, 0.05 * uncorrected);
    if (previous > 0.0) {
      EXPECT_NEAR(previous / total, 4.0, 0.4);
    }
    previous = total;
  }
}

// Monte Carlo of the noisy integration (independent white noise on every sample, Kalibr
// discretisation sigma = density / sqrt(dt)) against the propagated covariance.
TEST(ImuPreintegration, CovarianceMatchesMonteCarlo) {
  const auto samples = HelixSamples(0.5, 0.5, 100.0);
  const double dt = 0.01;
  const ImuNoise noise;  // defaults
  ImuPreintegration nominal(noise, ImuBias{});
  for (const auto& s : samples) nominal.Integrate(s);

  auto rng = MakeRng(42, "imu_preintegration_mc");
  NormalSampler normal;
  const int runs = 4000;
  std::vector<Vec9> errors;
  errors.reserve(runs);
  const double sg = noise.gyro_noise_density / std::sqrt(dt);
  const double sa = noise.accel_noise_density / std::sqrt(dt);
  for (int r = 0; r < runs; ++r) {
    ImuPreintegration noisy(noise, ImuBias{});
    for (const auto& s : samples) {
      const Vec3 ng(normal(rng), normal(rng), normal(rng));
      const Vec3 na(normal(rng), normal(rng), normal(rng));
      noisy.Integrate(s.header.stamp_ns, s.gyro + sg * ng, s.accel + sa * na);
    }
    Vec9 e;
    e.segment<3>(kPreintRotation) =
        so3::Log<double>(nominal.delta_q().conjugate() * noisy.delta_q());
    e.segment<3>(kPreintVelocity) = noisy.delta_v() - nominal.delta_v();
    e.segment<3>(kPreintPosition) = noisy.delta_p() - nominal.delta_p();
    errors.push_back(e);
  }
  Vec9 mean = Vec9::Zero();
  for (const auto& e : errors) mean += e / runs;
  Mat9 cov_mc = Mat9::Zero();
  for (const auto& e : errors) cov_mc += (e - mean) * (e - mean).transpose() / (runs - 1);

  const Mat9& cov = nominal.covariance();
  const Vec9 sd = cov.diagonal().cwiseSqrt();
  double worst_ratio = 0.0, worst_corr = 0.0;
  for (int i = 0; i < 9; ++i) {
    const double ratio = cov_mc(i, i) / cov(i, i);
    worst_ratio = std::max(worst_ratio, std::abs(ratio - 1.0));
    EXPECT_NEAR(ratio, 1.0, 0.10) << "variance " << i;
    for (int j = 0; j < i; ++j) {
      const double d = (cov_mc(i, j) - cov(i, j)) / (sd(i) * sd(j));
      worst_corr = std::max(worst_corr, std::abs(d));
      EXPECT_LT(std::abs(d), 0.10) << "correlation " << i << "," << j;
    }
  }
  std::printf("MC %d runs: worst variance ratio deviation %.3f, worst correlation deviation %.3f\n",
              runs, worst_ratio, worst_corr);
  // The covariance must be invertible even for a single step (integration noise).
  ImuPreintegration one_step(noise, ImuBias{});
  one_step.Integrate(samples[0]);
  one_step.Integrate(samples[1]);
  Eigen::LLT<Mat9> llt(one_step.covariance());
  EXPECT_EQ(llt.info(), Eigen::Success);
}

TEST(ImuPreintegration, RejectsBadSamplesAndKeepsState) {
  ImuPreintegration pim(ImuNoise{}, ImuBias{});
  pim.Integrate(1000, Vec3(0.1, 0, 0), Vec3(0, 0, 9.8));
  pim.Integrate(2000, Vec3(0.1, 0, 0), Vec3(0, 0, 9.8));
  const Vec3 dv = pim.delta_v();
  EXPECT_THROW(pim.Integrate(2000, Vec3::Zero(), Vec3::Zero()), InputError);
  EXPECT_THROW(pim.Integrate(1500, Vec3::Zero(), Vec3::Zero()), InputError);
  EXPECT_THROW(pim.Integrate(3000, Vec3(std::nan(""), 0, 0), Vec3::Zero()), InputError);
  EXPECT_EQ(pim.num_steps(), 1);
  EXPECT_EQ(pim.end_ns(), 2000);
  EXPECT_EQ(pim.delta_v(), dv);
}

// A preintegration made from one buffer may stand for FromSamples on another only when that one
// holds the very samples it integrated, the interpolation context before its start included.
TEST(ImuPreintegration, IntegratesSamplesOfNeedsTheSameSamplesAndContext) {
  const std::vector<ImuSample> samples = HelixSamples(1.0, 0.2, 100.0, /*context=*/5);
  const TimeNs t0 = samples[5].header.stamp_ns;
  const TimeNs t1 = samples[15].header.stamp_ns;
  const ImuPreintegration direct = ImuPreintegration::FromSamples(samples, t0, t1, ImuNoise{}, {});
  EXPECT_TRUE(direct.IntegratesSamplesOf(samples));
  // Extended sample by sample from its start: the same samples, and the same bits.
  ImuPreintegration extended = ImuPreintegration::FromSamples(samples, t0, t0, ImuNoise{}, {});
  for (std::size_t k = 6; k <= 15; ++k) extended.Integrate(samples[k]);
  EXPECT_TRUE(extended.IntegratesSamplesOf(samples));
  EXPECT_EQ(extended.delta_p(), direct.delta_p());
  EXPECT_EQ(extended.covariance(), direct.covariance());
  // Another buffer: shorter context (the stencil would shrink), a sample's bits changed, a
  // sample missing, or not covering the interval.
  EXPECT_FALSE(direct.IntegratesSamplesOf(std::span<const ImuSample>(samples).subspan(4)));
  EXPECT_TRUE(direct.IntegratesSamplesOf(std::span<const ImuSample>(samples).subspan(2)));
  std::vector<ImuSample> changed = samples;
  changed[3].gyro.x() = std::nextafter(changed[3].gyro.x(), 1.0);
  EXPECT_FALSE(direct.IntegratesSamplesOf(changed));
  std::vector<ImuSample> missing = samples;
  missing.erase(missing.begin() + 10);
  EXPECT_FALSE(direct.IntegratesSamplesOf(missing));
  EXPECT_FALSE(direct.IntegratesSamplesOf(std::span<const ImuSample>(samples).first(15)));
}

}  // namespace
}  // namespace statebench::est
