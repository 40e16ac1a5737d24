#include "estimator/gnss_time_offset_factor.hpp"

#include <gtest/gtest.h>

#include "core/random.hpp"
#include "core/so3.hpp"
#include "estimator/so3_manifold.hpp"
#include "estimator/state_parameters.hpp"
#include "helix_trajectory.hpp"
#include "jacobian_check.hpp"

namespace statebench::est {
namespace {

using testing::HelixTrajectory;

const Vec3 kOffsetLever(0.8, 0.3, 1.5);

std::vector<std::vector<double>> OffsetBlocks(const NavState& s, double offset_s) {
  const auto p = StateParameters::FromNavState(s);
  auto v = [](const auto& a) { return std::vector<double>(a.begin(), a.end()); };
  return {v(p.q_world_imu), v(p.p_world), v(p.v_world), v(p.bias), {offset_s}};
}

Vec3 Residual(const GnssTimeOffsetFactor& f, const NavState& s, double offset_s) {
  const auto blocks = OffsetBlocks(s, offset_s);
  const double* ptrs[] = {blocks[0].data(), blocks[1].data(), blocks[2].data(), blocks[3].data(),
                          blocks[4].data()};
  Vec3 r;
  f.Evaluate(ptrs, r.data(), nullptr);
  return r;
}

// A fix taken at t - d but stamped t (the receiver's stamps are late by d = 80 ms) is explained
// by the offset d: the residual at d is the first-order shift's error (1/2 |a| d^2 with the
// antenna's acceleration a, centimetres on the helix), at d = 0 the antenna's motion over 80 ms
// (decimetres).
TEST(GnssTimeOffsetFactor, ExplainsAFixStampedLate) {
  const HelixTrajectory helix;
  const auto samples = testing::HelixSamples(Vec3::Zero(), Vec3::Zero());
  const TimeNs t_i = FromSeconds(1.2);
  const TimeNs t_stamp = FromSeconds(1.2734);
  const double d = 0.08;
  const NavState taken = helix.State(t_stamp - FromSeconds(d));
  const Vec3 z = taken.p_world + taken.q_world_imu * kOffsetLever;
  const NavState state_i = helix.State(t_i);
  const GnssTimeOffsetFactor factor(
      z, 1e-4 * Mat3::Identity(), kOffsetLever,
      ImuPreintegration::FromSamples(samples, t_i, t_stamp, ImuNoise{}, ImuBias{}),
      state_i.q_world_imu, helix.Gyro(ToSeconds(t_stamp)));
  const double at_offset = 0.01 * Residual(factor, state_i, d).norm();  // whitened by 1/0.01 m
  const double at_zero = 0.01 * Residual(factor, state_i, 0.0).norm();
  const double speed = helix.Velocity(ToSeconds(t_stamp)).norm();
  std::printf("fix stamped 80 ms late: residual %.2e m with the offset, %.3f m without (%.1f m/s)\n",
              at_offset, at_zero, speed);
  // The antenna's acceleration bounds the first-order error (the lever arm's rotation adds a
  // little: 1.2 x and 1 mm spare).
  const double accel = helix.Acceleration(ToSeconds(t_stamp)).norm();
  std::printf("first-order bound 1/2 |a| d^2 = %.2e m (|a| = %.1f m/s^2)\n",
              0.5 * accel * d * d, accel);
  EXPECT_LT(at_offset, 1.2 * 0.5 * accel * d * d + 1e-3);
  EXPECT_GT(at_zero, 0.5 * d * speed);
}

TEST(GnssTimeOffsetFactor, JacobiansMatchNumericDifferencesOnTheManifold) {
  const HelixTrajectory helix;
  const RightQuaternionManifold so3_manifold;
  auto rng = MakeRng(37, "gnss_time_offset_jacobians");
  NormalSampler normal;
  const auto samples = testing::HelixSamples(Vec3::Zero(), Vec3::Zero());
  const auto r3 = [&] { return Vec3(normal(rng), normal(rng), normal(rng)); };
  double worst = 0.0;
  for (double tau : {0.0, 0.0734, 0.5}) {
    const TimeNs t_i = FromSeconds(1.0);
    const ImuBias bias_lin{Vec3(0.001, 0.0, -0.002), Vec3(0.0, 0.03, 0.0)};
    const NavState s = helix.State(t_i);
    const GnssTimeOffsetFactor factor(
        s.p_world + r3(), 1e-4 * Mat3::Identity(), kOffsetLever,
        ImuPreintegration::FromSamples(samples, t_i, t_i + FromSeconds(tau), ImuNoise{}, bias_lin),
        s.q_world_imu, helix.Gyro(1.0 + tau) + 0.1 * r3());
    for (int trial = 0; trial < 5; ++trial) {
      const NavState x = testing::PerturbedState(s, r3);
      const double offset = 0.1 * normal(rng);
      const auto check = testing::CheckJacobians(
          factor, OffsetBlocks(x, offset), {&so3_manifold, nullptr, nullptr, nullptr, nullptr},
          1e-6, trial == 0 ? "gnss time offset" : "");
      worst = std::max(worst, check.worst_relative_error);
    }
  }
  std::printf("gnss time offset factor: worst relative Jacobian error %.2e\n", worst);
  EXPECT_LT(worst, 1e-6);
}

}  // namespace
}  // namespace statebench::est
