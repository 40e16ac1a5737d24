#include "estimator/dual_antenna_factor.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <numbers>

#include "core/error.hpp"
#include "core/random.hpp"
#include "core/so3.hpp"
#include "estimator/so3_manifold.hpp"
#include "jacobian_check.hpp"

namespace statebench::est {
namespace {

// Measurement as the receiver forms it (sensors/dual_antenna_heading.hpp) from exact antennas.
DualAntennaHeading Measure(const Quat& q, const Vec3& main, const Vec3& aux, double sigma) {
  const Vec3 b = q * (aux - main);
  DualAntennaHeading m;
  m.header.sensor_id = "dual";
  m.yaw_rad = std::atan2(b.y(), b.x());
  m.pitch_rad = std::atan2(-b.z(), std::hypot(b.x(), b.y()));
  m.yaw_sigma_rad = sigma;
  m.pitch_sigma_rad = 2 * sigma;
  return m;
}

Vec2 Residual(const ceres::CostFunction& f, const Quat& q) {
  const double* ptrs[] = {q.coeffs().data()};
  Vec2 r;
  f.Evaluate(ptrs, r.data(), nullptr);
  return r;
}

const Vec3 kRear(-0.9, 0.0, 1.7), kFront(1.1, 0.0, 1.7);

TEST(DualAntennaFactor, AlongBodyXMatchesVehicleYawAndPitch) {
  const Quat q = so3::FromRollPitchYaw(0.03, -0.05, 1.0);
  const Vec3 rpy = so3::ToRollPitchYaw(q);
  DualAntennaHeading m;
  m.yaw_rad = rpy.z();
  m.pitch_rad = rpy.y();
  m.yaw_sigma_rad = 0.01;
  m.pitch_sigma_rad = 0.01;
  const std::unique_ptr<ceres::CostFunction> f(DualAntennaFactor::Create(m, kRear, kFront));
  EXPECT_LT(Residual(*f, q).norm(), 1e-12);
  // 0.01 rad more yaw is one sigma.
  EXPECT_NEAR(Residual(*f, so3::FromRollPitchYaw(0.03, -0.05, 1.01))(0), 1.0, 1e-3);
}

TEST(DualAntennaFactor, ArbitraryBaselineAndYawWrapAround) {
  // Lateral baseline (antennas left and right) and a heading across +-pi.
  const Vec3 left(0.2, 0.7, 1.5), right(0.1, -0.8, 1.4);
  const Quat q_meas = so3::FromRollPitchYaw(0.02, 0.01, std::numbers::pi - 0.002);
  const auto m = Measure(q_meas, right, left, 0.005);
  const std::unique_ptr<ceres::CostFunction> f(DualAntennaFactor::Create(m, right, left));
  EXPECT_LT(Residual(*f, q_meas).norm(), 1e-10);
  // The state's yaw just across -pi: 0.004 rad away, not 2 pi.
  const Quat q_state = q_meas * so3::Exp<double>(Vec3(0, 0, 0.004));
  const Vec2 r = Residual(*f, q_state);
  EXPECT_NEAR(std::abs(r(0)) * 0.005, 0.004, 2e-4);
}

TEST(DualAntennaFactor, HeadingBetweenStatesUsesTheImuRotationDelta) {
  const Quat q_i = so3::FromRollPitchYaw(0.01, 0.02, 0.3);
  const Quat dR = so3::Exp<double>(Vec3(0.001, -0.002, 0.005));  // 10 ms at 0.5 rad/s yaw
  const auto m = Measure(q_i * dR, kRear, kFront, 0.002);
  const std::unique_ptr<ceres::CostFunction> with_delta(
      DualAntennaFactor::Create(m, kRear, kFront, dR));
  const std::unique_ptr<ceres::CostFunction> without(DualAntennaFactor::Create(m, kRear, kFront));
  EXPECT_LT(Residual(*with_delta, q_i).norm(), 1e-10);
  EXPECT_GT(Residual(*without, q_i).norm(), 2.0);  // 5 mrad of yaw is 2.5 sigma
}

TEST(DualAntennaFactor, YawOnlyWhenPitchSigmaMissingAndRejectsBadInput) {
  const Quat q = so3::FromRollPitchYaw(0.0, 0.2, 0.5);
  DualAntennaHeading m = Measure(q, kRear, kFront, 0.01);
  m.pitch_rad = 0.0;  // wrong, but unused
  m.pitch_sigma_rad = 0.0;
  const std::unique_ptr<ceres::CostFunction> f(DualAntennaFactor::Create(m, kRear, kFront));
  EXPECT_EQ(Residual(*f, q)(1), 0.0);
  EXPECT_LT(std::abs(Residual(*f, q)(0)), 1e-10);

  m.yaw_sigma_rad = 0.0;
  EXPECT_THROW(DualAntennaFactor(m, kRear, kFront), InputError);
  m.yaw_sigma_rad = 0.01;
  EXPECT_THROW(DualAntennaFactor(m, kRear, kRear + Vec3(0, 0, 0.001)), InputError);
  EXPECT_THROW(DualAntennaFactor(m, kRear, kRear + Vec3(0, 0, 1.0)), InputError);  // vertical
}

TEST(DualAntennaFactor, JacobiansMatchNumericDifferencesOnTheManifold) {
  const RightQuaternionManifold so3_manifold;
  auto rng = MakeRng(41, "dual_antenna_jacobians");
  NormalSampler normal;
  double worst = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 rpy(0.1 * normal(rng), 0.1 * normal(rng),
                   std::numbers::pi * (2 * Uniform01(rng) - 1));
    const Quat q = so3::FromRollPitchYaw(rpy.x(), rpy.y(), rpy.z());
    // Measured a little off the state, including across the wrap.
    const auto m = Measure(q * so3::Exp<double>(0.02 * Vec3(normal(rng), normal(rng), normal(rng))),
                           kRear, kFront + Vec3(0.0, 0.3, 0.1), 0.01);
    const std::unique_ptr<ceres::CostFunction> f(
        DualAntennaFactor::Create(m, kRear, kFront + Vec3(0.0, 0.3, 0.1)));
    const auto check =
        testing::CheckJacobians(*f, {{q.coeffs().data(), q.coeffs().data() + 4}}, {&so3_manifold});
    worst = std::max(worst, check.worst_relative_error);
  }
  std::printf("dual antenna factor: worst relative Jacobian error %.2e\n", worst);
  EXPECT_LT(worst, 1e-7);
}

// The baseline measured by hand is off: the antennas' true baseline is the setup's turned by
// (c_yaw, c_pitch). The corrected factor explains the true headings with those corrections; the
// plain one sees them as an attitude error. Any baseline direction (here along x, then across).
TEST(DualAntennaFactor, BaselineCorrectionTurnsTheSetupsBaseline) {
  const Quat q = so3::FromRollPitchYaw(0.02, -0.03, 0.7);
  const Quat dR = so3::Exp<double>(Vec3(0.001, -0.002, 0.005));
  const double c_yaw = 0.012, c_pitch = -0.008;
  for (const Vec3& aux : {kFront, Vec3(-0.8, 0.9, 1.6)}) {
    const Vec3 b_setup = aux - kRear;
    const Vec3 b_true = DualAntennaFactor::TurnedBaseline(b_setup, c_yaw, c_pitch);
    EXPECT_NEAR(b_true.norm(), b_setup.norm(), 1e-12);
    const auto m = Measure(q * dR, Vec3::Zero(), b_true, 0.002);
    const std::unique_ptr<ceres::CostFunction> corrected(
        DualAntennaFactor::CreateWithBaselineCorrection(m, kRear, aux, dR));
    const std::unique_ptr<ceres::CostFunction> plain(DualAntennaFactor::Create(m, kRear, aux, dR));
    const double* at_truth[] = {q.coeffs().data(), &c_yaw, &c_pitch};
    Vec2 r;
    ASSERT_TRUE(corrected->Evaluate(at_truth, r.data(), nullptr));
    EXPECT_LT(r.norm(), 1e-10);
    EXPECT_GT(Residual(*plain, q).norm(), 3.0);
    const double zero = 0.0;
    const double* uncorrected[] = {q.coeffs().data(), &zero, &zero};
    Vec2 r0;
    ASSERT_TRUE(corrected->Evaluate(uncorrected, r0.data(), nullptr));
    EXPECT_NEAR((r0 - Residual(*plain, q)).norm(), 0.0, 1e-12);
  }
  // Along x on a level vehicle the corrections add to the predicted yaw and pitch as they are.
  const Vec3 b = DualAntennaFactor::TurnedBaseline(Vec3(2.0, 0.0, 0.0), 0.01, 0.02);
  EXPECT_NEAR(std::atan2(b.y(), b.x()), 0.01, 1e-12);
  EXPECT_NEAR(std::atan2(-b.z(), std::hypot(b.x(), b.y())), 0.02, 1e-12);

  const RightQuaternionManifold so3_manifold;
  const auto m = Measure(q, kRear, kFront + Vec3(0.0, 0.3, 0.1), 0.01);
  const std::unique_ptr<ceres::CostFunction> f(
      DualAntennaFactor::CreateWithBaselineCorrection(m, kRear, kFront + Vec3(0.0, 0.3, 0.1), dR));
  const auto check =
      testing::CheckJacobians(*f, {{q.coeffs().data(), q.coeffs().data() + 4}, {0.004}, {-0.006}},
                              {&so3_manifold, nullptr, nullptr});
  EXPECT_LT(check.worst_relative_error, 1e-7);
}

}  // namespace
}  // namespace statebench::est
