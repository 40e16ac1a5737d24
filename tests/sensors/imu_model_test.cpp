#include "sensors/imu_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "core/state.hpp"
#include "sensors/allan.hpp"
#include "truth_fixtures.hpp"

namespace statebench::sensors {
namespace {

SensorSpec ImuSpec(double rate_hz, const SE3& T_body_imu = SE3()) {
  SensorSpec spec;
  spec.id = "imu";
  spec.rate_hz = rate_hz;
  spec.T_body_sensor = T_body_imu;
  return spec;
}

// Two hours of static data at 200 Hz through the full model (turn-on bias, scale factor,
// misalignment and quantisation of the industrial preset included). The Allan deviation gives
// back the configured noise density (-1/2 line at tau = 1 s) and bias random walk (+1/2 line at
// tau = 3 s) of every axis within 10 %.
TEST(ImuModel, AllanDeviationRecoversNoiseDensityAndRandomWalk) {
  const ImuOptions options = ImuPreset(ImuGrade::kIndustrial);
  ImuModel imu(ImuSpec(200.0, SE3(Quat::Identity(), Vec3(0.1, 0.0, 0.55))), options, 42);
  const int n = 200 * 7200;
  const double dt = 1.0 / 200.0;
  std::vector<std::vector<double>> series(6, std::vector<double>(n));
  for (int k = 0; k < n; ++k) {
    const ImuSample s = imu.Sample(testing::StaticTruth(k * 5 * kNsPerMillisecond));
    for (int i = 0; i < 3; ++i) {
      series[i][k] = s.gyro[i];
      series[3 + i][k] = s.accel[i];
    }
  }
  const std::vector<int> sizes = LogSpacedClusterSizes(n / 4, 10);
  for (int i = 0; i < 6; ++i) {
    const bool gyro = i < 3;
    const ImuTriadOptions& expected = gyro ? options.gyro : options.accel;
    const std::vector<AllanPoint> curve = OverlappingAllanDeviation(series[i], dt, sizes);
    const NoiseFit fit = FitWhiteNoiseAndRandomWalk(curve, 0.1, 7200.0 / 20.0);
    const double n_ratio = fit.noise_density / expected.noise_density;
    const double k_ratio = fit.random_walk / expected.random_walk;
    SCOPED_TRACE((gyro ? "gyro axis " : "accel axis ") + std::to_string(i % 3));
    EXPECT_GE(fit.white_points, 5);
    EXPECT_GE(fit.rw_points, 5);
    EXPECT_NEAR(n_ratio, 1.0, 0.10);
    EXPECT_NEAR(k_ratio, 1.0, 0.10);
    // Two hours leave only ~1.4 decades of random-walk-dominated gyro curve (crossover ~15 s):
    // the free slope scatters by ~0.05; 0.15 still tells it from flicker (0) or ramp (+1).
    EXPECT_NEAR(fit.rw_slope, 0.5, 0.15);
    std::printf("[ measured ] %s axis %d: density ratio %.3f, random-walk ratio %.3f, slope %.3f\n",
                gyro ? "gyro " : "accel", i % 3, n_ratio, k_ratio, fit.rw_slope);
  }
}

// Without errors, the IMU on a lever arm of a body driving a circle reads the exact rate and
// specific force of its mount (centripetal acceleration of the mount, not of the body origin).
TEST(ImuModel, NoiseFreeImuReadsExactKinematicsAtItsMount) {
  const SE3 T_body_imu(so3::FromRollPitchYaw(0.0, 0.0, 0.3), Vec3(0.8, 0.4, 0.55));
  ImuModel imu(ImuSpec(100.0, T_body_imu), ImuOptions{}, 1);
  const testing::Circle circle;
  const TruthSample truth = circle.At(3 * kNsPerSecond);
  const ImuSample s = imu.Sample(truth);
  const FrameKinematics expected = truth.body.AtMount(T_body_imu);
  EXPECT_LT((s.gyro - expected.omega_frame).norm(), 1e-12);
  EXPECT_LT((s.accel - expected.SpecificForce()).norm(), 1e-12);
  // The mount sits further out than the body origin: its centripetal acceleration is larger.
  const Vec3 p_world_imu = truth.body.T_world_frame * T_body_imu.translation();
  const double r_imu = (p_world_imu - circle.centre).head<2>().norm();
  const double w = circle.speed_mps / circle.radius_m;
  EXPECT_NEAR(Vec2(s.accel.x(), s.accel.y()).norm(), w * w * r_imu, 1e-9);
  EXPECT_NEAR(s.accel.z(), kGravity, 1e-12);
}

TEST(ImuModel, ScaleFactorMisalignmentAndTurnOnBiasAreAppliedAsDrawn) {
  ImuOptions o;
  o.gyro.scale_factor_sigma = 1e-2;
  o.gyro.misalignment_sigma_rad = 1e-2;
  o.gyro.turn_on_bias_sigma = 1e-3;
  ImuModel imu(ImuSpec(100.0), o, 7);
  const Mat3& m = imu.gyro_errors().sensitivity();
  EXPECT_GT((m - Mat3::Identity()).cwiseAbs().minCoeff(), 0.0);  // every term drawn
  EXPECT_LT((m - Mat3::Identity()).cwiseAbs().maxCoeff(), 5e-2);
  TruthSample truth = testing::StaticTruth(0);
  truth.body.omega_frame = Vec3(0.5, -0.2, 1.0);
  const ImuSample s = imu.Sample(truth);
  const Vec3 expected = m * truth.body.omega_frame + imu.gyro_errors().CurrentBias();
  EXPECT_LT((s.gyro - expected).norm(), 1e-15);
  EXPECT_GT(imu.gyro_errors().CurrentBias().norm(), 0.0);
  EXPECT_EQ(imu.accel_errors().sensitivity(), Mat3::Identity());
}

TEST(ImuModel, QuantisedOutputIsAMultipleOfTheStep) {
  ImuOptions o = ImuPreset(ImuGrade::kConsumer);
  ImuModel imu(ImuSpec(200.0), o, 3);
  for (int k = 0; k < 200; ++k) {
    const ImuSample s = imu.Sample(testing::StaticTruth(k * 5 * kNsPerMillisecond));
    for (int i = 0; i < 3; ++i) {
      const double g = s.gyro[i] / o.gyro.quantization;
      const double a = s.accel[i] / o.accel.quantization;
      EXPECT_NEAR(g, std::round(g), 1e-6);
      EXPECT_NEAR(a, std::round(a), 1e-6);
    }
  }
}

// The Gauss-Markov bias holds its stationary sigma (exact discretisation): over many
// independent runs the bias after 10 tau has the configured standard deviation.
TEST(ImuModel, GaussMarkovBiasIsStationary) {
  ImuOptions o;
  o.gyro.gauss_markov_sigma = 2e-3;
  o.gyro.gauss_markov_tau_s = 0.5;
  double sum_sq = 0.0;
  const int runs = 2000;
  for (int r = 0; r < runs; ++r) {
    ImuModel imu(ImuSpec(100.0), o, 1000 + r);
    for (int k = 0; k < 500; ++k) imu.Sample(testing::StaticTruth(k * 10 * kNsPerMillisecond));
    sum_sq += imu.gyro_errors().CurrentBias().squaredNorm();
  }
  const double sigma = std::sqrt(sum_sq / (3.0 * runs));
  EXPECT_NEAR(sigma / o.gyro.gauss_markov_sigma, 1.0, 0.05);  // 6000 samples: ~1 % std
}

TEST(ImuModel, ObserveSamplesOnlyAtItsRate) {
  ImuModel imu(ImuSpec(200.0, SE3()), ImuPreset(ImuGrade::kTactical), 5);
  std::vector<Measurement> out;
  for (int k = 0; k < 1000; ++k) imu.Observe(testing::StaticTruth(k * kNsPerMillisecond), &out);
  ASSERT_EQ(out.size(), 200u);
  EXPECT_EQ(HeaderOf(out[1]).stamp_ns, 5 * kNsPerMillisecond);
}

}  // namespace
}  // namespace statebench::sensors
