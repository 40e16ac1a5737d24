#include "estimator/body_velocity_factor.hpp"

#include <gtest/gtest.h>

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

std::vector<ImuSample> Samples(const ImuBias& bias) {
  return testing::HelixSamples(bias.gyro, bias.accel);
}

std::vector<double> Vec(const auto& a) { return std::vector<double>(a.begin(), a.end()); }

std::vector<std::vector<double>> Blocks(const NavState& s) {
  const auto p = StateParameters::FromNavState(s);
  return {Vec(p.q_world_imu), Vec(p.v_world), Vec(p.bias)};
}

Vec3 Evaluate(const ceres::CostFunction& f, const NavState& s) {
  const auto b = Blocks(s);
  const double* ptrs[] = {b[0].data(), b[1].data(), b[2].data()};
  Vec3 r;
  f.Evaluate(ptrs, r.data(), nullptr);
  return r;
}

// The velocity of a point 1.2 m behind and 0.4 m below the IMU, in a frame yawed 0.3 rad,
// measured 43 ms after the state: zero residual at the truth (biased gyro, bias known).
TEST(BodyVelocityFactor, ZeroResidualAtTheTruth) {
  const HelixTrajectory helix;
  const ImuBias bias{Vec3(0.003, -0.002, 0.001), Vec3(0.05, -0.04, 0.08)};
  const auto samples = Samples(bias);
  const TimeNs t_a = FromSeconds(1.5), t = FromSeconds(1.543);
  BodyVelocityMeasurement m;
  m.p_imu_point = Vec3(-1.2, 0.1, -0.4);
  m.q_imu_frame = Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ()));
  m.sqrt_information = Mat3::Identity() * 10.0;
  m.gyro_raw = helix.Gyro(ToSeconds(t)) + bias.gyro;
  const NavState truth = helix.State(t);
  const Vec3 omega = helix.Gyro(ToSeconds(t));
  m.v_frame = m.q_imu_frame.conjugate() *
              (truth.q_world_imu.conjugate() * truth.v_world + omega.cross(m.p_imu_point));
  const std::unique_ptr<ceres::CostFunction> f(CreateBodyVelocityFactor(
      m, ImuPreintegration::FromSamples(samples, t_a, t, ImuNoise{},
                                        ImuBias{0.9 * bias.gyro, 0.9 * bias.accel})));
  NavState a = helix.State(t_a);
  a.gyro_bias = bias.gyro;
  a.accel_bias = bias.accel;
  const Vec3 r = Evaluate(*f, a) / 10.0;
  std::printf("body velocity 43 ms after the state: residual %.2e m/s\n", r.norm());
  EXPECT_LT(r.norm(), 1e-6);
  // A wrong lever arm is visible: the helix turns, so the point's velocity differs.
  BodyVelocityMeasurement wrong = m;
  wrong.p_imu_point = Vec3::Zero();
  const std::unique_ptr<ceres::CostFunction> g(
      CreateBodyVelocityFactor(wrong, ImuPreintegration::FromSamples(samples, t_a, t, ImuNoise{},
                                                                     ImuBias{})));
  EXPECT_GT((Evaluate(*g, a) / 10.0).norm(), 1e-2);
}

// A GNSS receiver's Doppler velocity of its antenna, in ENU (Frame::kWorld): v + R (w x l) at
// the stamp, 70 ms after the state, zero residual at the truth; the lever-arm term counts.
TEST(BodyVelocityFactor, GnssVelocityInTheWorldFrameIsZeroAtTheTruth) {
  const HelixTrajectory helix;
  const ImuBias bias{Vec3(0.003, -0.002, 0.001), Vec3(0.05, -0.04, 0.08)};
  const auto samples = Samples(bias);
  const TimeNs t_a = FromSeconds(2.0), t = FromSeconds(2.07);
  BodyVelocityMeasurement m;
  m.frame = BodyVelocityMeasurement::Frame::kWorld;
  m.p_imu_point = Vec3(0.45, 0.0, 1.5);  // antenna lever arm
  m.sqrt_information = Vec3(1 / 0.07, 1 / 0.07, 1 / 0.12).asDiagonal();
  m.gyro_raw = helix.Gyro(ToSeconds(t)) + bias.gyro;
  const NavState truth = helix.State(t);
  m.v_frame = truth.v_world + truth.q_world_imu * helix.Gyro(ToSeconds(t)).cross(m.p_imu_point);
  const auto propagation = ImuPreintegration::FromSamples(samples, t_a, t, ImuNoise{}, bias);
  const std::unique_ptr<ceres::CostFunction> f(CreateBodyVelocityFactor(m, propagation));
  NavState a = helix.State(t_a);
  a.gyro_bias = bias.gyro;
  a.accel_bias = bias.accel;
  const Vec3 r = Evaluate(*f, a);
  std::printf("gnss velocity 70 ms after the state: whitened residual %.2e\n", r.norm());
  EXPECT_LT(r.norm(), 1e-4);
  // The lever-arm term is in: without it the residual is exactly -S R (w x l).
  BodyVelocityMeasurement no_lever = m;
  no_lever.p_imu_point = Vec3::Zero();
  const std::unique_ptr<ceres::CostFunction> g(CreateBodyVelocityFactor(no_lever, propagation));
  const Vec3 lever_term =
      m.sqrt_information * (truth.q_world_imu * helix.Gyro(ToSeconds(t)).cross(m.p_imu_point));
  EXPECT_LT((Evaluate(*g, a) + lever_term).norm(), 1e-4);
  EXPECT_GT(lever_term.norm(), 0.1);
}

TEST(BodyVelocityFactor, JacobiansMatchNumericDifferencesOnTheManifold) {
  const HelixTrajectory helix;
  const RightQuaternionManifold q_manifold;
  auto rng = MakeRng(43, "body_velocity_jacobians");
  NormalSampler normal;
  const auto r3 = [&] { return Vec3(normal(rng), normal(rng), normal(rng)); };
  const auto samples = Samples(ImuBias{});
  double worst = 0.0;
  using Frame = BodyVelocityMeasurement::Frame;
  for (const Frame frame : {Frame::kVehicle, Frame::kWorld}) {
    for (double tau : {0.0, 0.043, 0.3}) {
      const TimeNs t_a = FromSeconds(1.0);
      BodyVelocityMeasurement m;
      m.frame = frame;
      m.p_imu_point = r3();
      m.q_imu_frame = so3::Exp<double>(r3());
      m.v_frame = r3();
      m.gyro_raw = r3();
      m.sqrt_information = Vec3(0.0, 10.0, 20.0).asDiagonal();  // non-holonomic: y and z only
      m.sqrt_information(0, 0) = tau > 0.1 ? 5.0 : 0.0;
      const std::unique_ptr<ceres::CostFunction> f(CreateBodyVelocityFactor(
          m, ImuPreintegration::FromSamples(samples, t_a, t_a + FromSeconds(tau), ImuNoise{},
                                            ImuBias{Vec3(0.001, 0.0, 0.0), Vec3(0.0, 0.02, 0.0)})));
      for (int trial = 0; trial < 5; ++trial) {
        const NavState x = testing::PerturbedState(helix.State(t_a), r3);
        const auto check =
            testing::CheckJacobians(*f, Blocks(x), {&q_manifold, nullptr, nullptr}, 1e-6);
        worst = std::max(worst, check.worst_relative_error);
      }
    }
  }
  std::printf("body and gnss velocity factor: worst relative Jacobian error %.2e\n", worst);
  EXPECT_LT(worst, 1e-6);
}


// The vehicle frame turned by a mount correction c = (0, pitch, yaw): zero residual at the truth
// when the setup's frame is off by c, the wrong residual without the correction, and Jacobians
// (including the two scalar blocks) against numeric differences.
TEST(BodyVelocityFactor, MountCorrectionTurnsTheVehicleFrame) {
  const HelixTrajectory helix;
  const ImuBias bias{Vec3(0.003, -0.002, 0.001), Vec3(0.05, -0.04, 0.08)};
  const auto samples = Samples(bias);
  const TimeNs t_a = FromSeconds(1.5), t = FromSeconds(1.543);
  const double pitch = 0.02, yaw = -0.03;
  const Quat q_told(Eigen::AngleAxisd(0.3, Vec3::UnitZ()));
  const Quat q_true = q_told * so3::Exp<double>(Vec3(0.0, pitch, yaw));
  BodyVelocityMeasurement m;
  m.p_imu_point = Vec3(-1.2, 0.1, -0.4);
  m.q_imu_frame = q_told;
  m.sqrt_information = Mat3::Identity() * 10.0;
  m.gyro_raw = helix.Gyro(ToSeconds(t)) + bias.gyro;
  const NavState truth = helix.State(t);
  m.v_frame = q_true.conjugate() * (truth.q_world_imu.conjugate() * truth.v_world +
                                    helix.Gyro(ToSeconds(t)).cross(m.p_imu_point));
  const auto propagation = ImuPreintegration::FromSamples(samples, t_a, t, ImuNoise{}, bias);
  const std::unique_ptr<ceres::CostFunction> f(
      CreateMountCorrectedBodyVelocityFactor(m, propagation));
  NavState a = helix.State(t_a);
  a.gyro_bias = bias.gyro;
  a.accel_bias = bias.accel;
  auto blocks = Blocks(a);
  blocks.push_back({pitch});
  blocks.push_back({yaw});
  const double* ptrs[] = {blocks[0].data(), blocks[1].data(), blocks[2].data(), blocks[3].data(),
                          blocks[4].data()};
  Vec3 r;
  f->Evaluate(ptrs, r.data(), nullptr);
  EXPECT_LT(r.norm() / 10.0, 1e-6);
  const std::unique_ptr<ceres::CostFunction> plain(CreateBodyVelocityFactor(m, propagation));
  EXPECT_GT((Evaluate(*plain, a) / 10.0).norm(), 0.1 * 0.02);  // ~|v| x 0.036 rad

  const RightQuaternionManifold q_manifold;
  auto rng = MakeRng(44, "mount_corrected_body_velocity_jacobians");
  NormalSampler normal;
  const auto r3 = [&] { return Vec3(normal(rng), normal(rng), normal(rng)); };
  double worst = 0.0;
  for (double tau : {0.0, 0.043, 0.3}) {
    BodyVelocityMeasurement n;
    n.p_imu_point = r3();
    n.q_imu_frame = so3::Exp<double>(r3());
    n.v_frame = r3();
    n.gyro_raw = r3();
    n.sqrt_information = Vec3(5.0, 10.0, 20.0).asDiagonal();
    const std::unique_ptr<ceres::CostFunction> g(CreateMountCorrectedBodyVelocityFactor(
        n, ImuPreintegration::FromSamples(samples, t_a, t_a + FromSeconds(tau), ImuNoise{},
                                          ImuBias{Vec3(0.001, 0.0, 0.0), Vec3(0.0, 0.02, 0.0)})));
    for (int trial = 0; trial < 5; ++trial) {
      auto b = Blocks(testing::PerturbedState(helix.State(t_a), r3));
      b.push_back({0.05 * normal(rng)});
      b.push_back({0.05 * normal(rng)});
      const auto check = testing::CheckJacobians(
          *g, b, {&q_manifold, nullptr, nullptr, nullptr, nullptr}, 1e-6);
      worst = std::max(worst, check.worst_relative_error);
    }
  }
  std::printf("mount-corrected body velocity factor: worst relative Jacobian error %.2e\n", worst);
  EXPECT_LT(worst, 1e-6);
  // A world-frame measurement has no vehicle frame to turn.
  BodyVelocityMeasurement world = m;
  world.frame = BodyVelocityMeasurement::Frame::kWorld;
  EXPECT_THROW(CreateMountCorrectedBodyVelocityFactor(world, propagation), InputError);
}

}  // namespace
}  // namespace statebench::est
