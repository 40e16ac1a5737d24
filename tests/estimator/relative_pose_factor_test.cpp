#include "estimator/relative_pose_factor.hpp"

#include <gtest/gtest.h>

#include <initializer_list>
#include <memory>

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

// A lidar on a roof, yawed and tilted with respect to the IMU.
const SE3 kImuLidar(so3::Exp<double>(Vec3(0.02, -0.05, 0.7)), Vec3(-0.15, 0.1, 1.12));

std::vector<ImuSample> Samples(const ImuBias& bias) {
  return testing::HelixSamples(bias.gyro, bias.accel);
}

std::vector<double> Vec(const auto& a) { return std::vector<double>(a.begin(), a.end()); }

std::vector<std::vector<double>> RelativePoseBlocks(const NavState& s) {
  const auto p = StateParameters::FromNavState(s);
  return {Vec(p.q_world_imu), Vec(p.p_world), Vec(p.v_world), Vec(p.bias)};
}

SE3 PoseOf(const NavState& s) { return SE3(s.q_world_imu, s.p_world); }

NavState TrueStateWithBias(const HelixTrajectory& helix, TimeNs t, const ImuBias& bias) {
  NavState s = helix.State(t);
  s.gyro_bias = bias.gyro;
  s.accel_bias = bias.accel;
  return s;
}

// The blocks of the helix's states at the stamps, each perturbed by draws of r3 (a random Vec3).
template <typename Draw>
std::vector<std::vector<double>> PerturbedStateBlocks(const HelixTrajectory& helix,
                                                      std::initializer_list<TimeNs> stamps,
                                                      Draw& r3) {
  std::vector<std::vector<double>> blocks;
  for (TimeNs t : stamps) {
    for (auto& b : RelativePoseBlocks(testing::PerturbedState(helix.State(t), r3))) {
      blocks.push_back(b);
    }
  }
  return blocks;
}

Vec6 Evaluate(const ceres::CostFunction& f, const std::vector<std::vector<double>>& blocks) {
  std::vector<const double*> ptrs;
  for (const auto& b : blocks) ptrs.push_back(b.data());
  Vec6 r;
  f.Evaluate(ptrs.data(), r.data(), nullptr);
  return r;
}

// Scan stamps between IMU samples and between states, the states 0.1 s apart: the factor
// predicts the lidar motion between the scans' own stamps exactly (biased IMU, bias known).
TEST(RelativePoseFactor, ZeroResidualAtTheTruthBetweenStates) {
  const HelixTrajectory helix;
  const ImuBias bias{Vec3(0.003, -0.002, 0.001), Vec3(0.05, -0.04, 0.08)};
  const auto samples = Samples(bias);
  const TimeNs t_a = FromSeconds(1.2), t_b = FromSeconds(1.3);
  const TimeNs t1 = FromSeconds(1.2437), t2 = FromSeconds(1.3437);
  RelativePoseMeasurement m;
  m.T_imu_sensor = kImuLidar;
  m.T_s1_s2 = PredictedSensorMotion(PoseOf(helix.State(t1)), PoseOf(helix.State(t2)), kImuLidar);
  m.sqrt_information = Mat6::Identity() * 100.0;
  // Linearised 10 % off the true bias: the first-order correction takes up the difference.
  const ImuBias lin{0.9 * bias.gyro, 0.9 * bias.accel};
  const std::unique_ptr<ceres::CostFunction> f(CreateRelativePoseFactor(
      m, ImuPreintegration::FromSamples(samples, t_a, t1, ImuNoise{}, lin),
      ImuPreintegration::FromSamples(samples, t_b, t2, ImuNoise{}, lin)));
  const NavState a = TrueStateWithBias(helix, t_a, bias);
  auto blocks = RelativePoseBlocks(a);
  for (auto& blk : RelativePoseBlocks(TrueStateWithBias(helix, t_b, bias))) blocks.push_back(blk);
  const Vec6 r = Evaluate(*f, blocks) / 100.0;
  std::printf("relative pose at the scan stamps: residual %.2e (m, rad)\n", r.norm());
  EXPECT_LT(r.norm(), 1e-6);

  // The same pair from one anchor (both stamps after state a).
  const std::unique_ptr<ceres::CostFunction> one(CreateRelativePoseFactorOneAnchor(
      m, ImuPreintegration::FromSamples(samples, t_a, t1, ImuNoise{}, lin),
      ImuPreintegration::FromSamples(samples, t_a, t2, ImuNoise{}, lin)));
  EXPECT_LT((Evaluate(*one, RelativePoseBlocks(a)) / 100.0).norm(), 1e-6);

  // A 5 cm error along the lidar's x axis shows up as rho_x = 5 cm.
  RelativePoseMeasurement off = m;
  off.T_s1_s2 = m.T_s1_s2 * SE3(Quat::Identity(), Vec3(0.05, 0.0, 0.0));
  const std::unique_ptr<ceres::CostFunction> f_off(CreateRelativePoseFactor(
      off, ImuPreintegration::FromSamples(samples, t_a, t1, ImuNoise{}, lin),
      ImuPreintegration::FromSamples(samples, t_b, t2, ImuNoise{}, lin)));
  const Vec6 r_off = Evaluate(*f_off, blocks) / 100.0;
  EXPECT_NEAR(r_off(0), -0.05, 1e-5);
  EXPECT_LT(r_off.tail<5>().norm(), 1e-5);
}

TEST(RelativePoseFactor, JacobiansMatchNumericDifferencesOnTheManifold) {
  const HelixTrajectory helix;
  const RightQuaternionManifold q_manifold;
  auto rng = MakeRng(41, "relative_pose_jacobians");
  NormalSampler normal;
  const auto r3 = [&] { return Vec3(normal(rng), normal(rng), normal(rng)); };
  const auto samples = Samples(ImuBias{});
  const ImuBias lin{Vec3(0.001, 0.0, -0.002), Vec3(0.0, 0.03, 0.0)};
  const TimeNs t_a = FromSeconds(1.0), t_b = FromSeconds(1.1);
  const TimeNs t1 = FromSeconds(1.0412), t2 = FromSeconds(1.1412);
  RelativePoseMeasurement m;
  m.T_imu_sensor = kImuLidar;
  m.T_s1_s2 = SE3(so3::Exp<double>(0.05 * r3()), r3());
  Mat6 A = Mat6::Random();
  m.sqrt_information = SqrtOfInformation(A * A.transpose() + Mat6::Identity());
  const std::unique_ptr<ceres::CostFunction> two(CreateRelativePoseFactor(
      m, ImuPreintegration::FromSamples(samples, t_a, t1, ImuNoise{}, lin),
      ImuPreintegration::FromSamples(samples, t_b, t2, ImuNoise{}, lin)));
  const std::unique_ptr<ceres::CostFunction> one(CreateRelativePoseFactorOneAnchor(
      m, ImuPreintegration::FromSamples(samples, t_a, t1, ImuNoise{}, lin),
      ImuPreintegration::FromSamples(samples, t_a, t2, ImuNoise{}, lin)));
  double worst = 0.0;
  for (int trial = 0; trial < 5; ++trial) {
    const std::vector<std::vector<double>> blocks = PerturbedStateBlocks(helix, {t_a, t_b}, r3);
    const std::vector<const ceres::Manifold*> manifolds = {&q_manifold, nullptr, nullptr,
                                                           nullptr,     &q_manifold, nullptr,
                                                           nullptr,     nullptr};
    const auto check = testing::CheckJacobians(*two, blocks, manifolds, 1e-6);
    const std::vector<std::vector<double>> first(blocks.begin(), blocks.begin() + 4);
    const auto check_one = testing::CheckJacobians(
        *one, first, {&q_manifold, nullptr, nullptr, nullptr}, 1e-6);
    worst = std::max(worst, check.worst_relative_error);
    // With one anchor the position cancels out of the relative motion: its Jacobian is zero
    // and the numeric one round-off (checked in absolute terms).
    for (std::size_t b : {0u, 2u, 3u}) worst = std::max(worst, check_one.block_relative_error[b]);
    EXPECT_LT(check_one.block_max_entry[1], 1e-8);
  }
  std::printf("relative pose factor: worst relative Jacobian error %.2e\n", worst);
  EXPECT_LT(worst, 1e-6);
}

// The sensor frame turned by a mount correction c (roll, pitch, yaw, or pitch and yaw): zero
// residual at the truth when the setup's X is off by c (rotation only), a wrong one without the
// correction, and Jacobians (the correction's scalar blocks too) against numeric differences.
TEST(RelativePoseFactor, MountCorrectionTurnsTheSensorFrame) {
  const HelixTrajectory helix;
  const ImuBias bias{Vec3(0.003, -0.002, 0.001), Vec3(0.05, -0.04, 0.08)};
  const auto samples = Samples(bias);
  const TimeNs t_a = FromSeconds(1.2), t_b = FromSeconds(1.3);
  const TimeNs t1 = FromSeconds(1.2437), t2 = FromSeconds(1.3437);
  const Vec3 c(0.004, -0.003, 0.005);  // about 0.2-0.3 deg per axis
  const SE3 true_mount(kImuLidar.rotation() * so3::Exp<double>(c), kImuLidar.translation());
  RelativePoseMeasurement m;
  m.T_imu_sensor = kImuLidar;  // what the setup says
  m.T_s1_s2 = PredictedSensorMotion(PoseOf(helix.State(t1)), PoseOf(helix.State(t2)), true_mount);
  m.sqrt_information = Mat6::Identity() * 100.0;
  const auto to_t1 = ImuPreintegration::FromSamples(samples, t_a, t1, ImuNoise{}, bias);
  const auto to_t2 = ImuPreintegration::FromSamples(samples, t_b, t2, ImuNoise{}, bias);
  const NavState a = TrueStateWithBias(helix, t_a, bias);
  auto blocks = RelativePoseBlocks(a);
  for (auto& blk : RelativePoseBlocks(TrueStateWithBias(helix, t_b, bias))) blocks.push_back(blk);
  const std::unique_ptr<ceres::CostFunction> plain(CreateRelativePoseFactor(m, to_t1, to_t2));
  const std::unique_ptr<ceres::CostFunction> corrected(
      CreateRelativePoseFactor(m, to_t1, to_t2, MountAxes{true, true, true}));
  auto with_c = blocks;
  for (int i = 0; i < 3; ++i) with_c.push_back({c[i]});
  const double plain_error = (Evaluate(*plain, blocks) / 100.0).norm();
  const double corrected_error = (Evaluate(*corrected, with_c) / 100.0).norm();
  std::printf("mount off by 0.2-0.3 deg: residual %.2e without the correction, %.2e with it\n",
              plain_error, corrected_error);
  EXPECT_LT(corrected_error, 1e-6);
  EXPECT_GT(plain_error, 1e-4);
  // At c = 0 the corrected factor is the plain one.
  auto zero_c = blocks;
  for (int i = 0; i < 3; ++i) zero_c.push_back({0.0});
  EXPECT_LT((Evaluate(*corrected, zero_c) - Evaluate(*plain, blocks)).norm(), 1e-9);

  const RightQuaternionManifold q_manifold;
  auto rng = MakeRng(45, "mount_corrected_relative_pose_jacobians");
  NormalSampler normal;
  const auto r3 = [&] { return Vec3(normal(rng), normal(rng), normal(rng)); };
  double worst = 0.0;
  for (const MountAxes axes : {MountAxes{true, true, true}, MountAxes{false, true, true}}) {
    RelativePoseMeasurement n = m;
    n.T_s1_s2 = SE3(so3::Exp<double>(0.05 * r3()), r3());
    Mat6 A = Mat6::Random();
    n.sqrt_information = SqrtOfInformation(A * A.transpose() + Mat6::Identity());
    const std::unique_ptr<ceres::CostFunction> two(CreateRelativePoseFactor(n, to_t1, to_t2, axes));
    const std::unique_ptr<ceres::CostFunction> one(CreateRelativePoseFactorOneAnchor(
        n, to_t1, ImuPreintegration::FromSamples(samples, t_a, t2, ImuNoise{}, bias), axes));
    for (int trial = 0; trial < 4; ++trial) {
      const std::vector<std::vector<double>> states = PerturbedStateBlocks(helix, {t_a, t_b}, r3);
      std::vector<std::vector<double>> corrections;
      for (int i = 0; i < axes.count(); ++i) corrections.push_back({0.05 * normal(rng)});
      std::vector<std::vector<double>> all = states, first(states.begin(), states.begin() + 4);
      all.insert(all.end(), corrections.begin(), corrections.end());
      first.insert(first.end(), corrections.begin(), corrections.end());
      std::vector<const ceres::Manifold*> manifolds = {&q_manifold, nullptr, nullptr, nullptr,
                                                       &q_manifold, nullptr, nullptr, nullptr};
      std::vector<const ceres::Manifold*> first_manifolds = {&q_manifold, nullptr, nullptr,
                                                             nullptr};
      for (int i = 0; i < axes.count(); ++i) {
        manifolds.push_back(nullptr);
        first_manifolds.push_back(nullptr);
      }
      worst = std::max(worst, testing::CheckJacobians(*two, all, manifolds, 1e-6)
                                  .worst_relative_error);
      const auto check_one = testing::CheckJacobians(*one, first, first_manifolds, 1e-6);
      // One anchor: the position cancels out (its Jacobian is zero, the numeric one round-off).
      for (std::size_t k = 0; k < check_one.block_relative_error.size(); ++k) {
        if (k != 1) worst = std::max(worst, check_one.block_relative_error[k]);
      }
    }
  }
  std::printf("mount-corrected relative pose factor: worst relative Jacobian error %.2e\n", worst);
  EXPECT_LT(worst, 1e-6);
  // Roll alone or yaw alone: no such correction.
  EXPECT_THROW(CreateRelativePoseFactor(m, to_t1, to_t2, MountAxes{false, false, true}),
               InputError);
  EXPECT_THROW(CreateRelativePoseFactor(m, to_t1, to_t2, MountAxes{true, false, true}),
               InputError);
}

TEST(RelativePoseFactor, SqrtOfInformationHandlesRankDeficientInformation) {
  Mat6 info = Mat6::Zero();
  info(0, 0) = 4.0;
  info(1, 1) = 9.0;
  info(5, 5) = 100.0;
  info(0, 5) = info(5, 0) = 1.0;
  const Mat6 S = SqrtOfInformation(info);
  EXPECT_LT((S.transpose() * S - info).norm(), 1e-12);
  EXPECT_TRUE(S.allFinite());
}

}  // namespace
}  // namespace statebench::est
