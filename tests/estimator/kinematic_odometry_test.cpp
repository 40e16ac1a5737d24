#include "estimator/kinematic_odometry.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/error.hpp"
#include "core/so3.hpp"

namespace statebench::est {
namespace {

constexpr double kWheelbase = 1.69;

// Encoders at 50 Hz on a constant circle: V_x along the rear-axle x axis, front angle delta.
std::optional<KinematicMotion> DriveCircle(KinematicOdometry& odo, double v_x, double delta,
                                           int samples) {
  std::optional<KinematicMotion> out;
  for (int k = 0; k <= samples; ++k) {
    const TimeNs t = k * 20 * kNsPerMillisecond;
    odo.AddSteering(t, delta);
    if (auto m = odo.AddSpeed(t, v_x)) out = m;
  }
  return out;
}

// Closed form: the rear-axle frame turns at w = V_x (tan(delta) - tan(delta_r)) / l and moves
// with (V_x, V_x tan(delta_r)) in its own axes.
Vec3 ExactArc(double v_x, double delta, double ratio, double T) {
  const double tr = std::tan(-ratio * delta);
  const double w = v_x * (std::tan(delta) - tr) / kWheelbase;
  const double psi = w * T;
  return Vec3(v_x / w * (std::sin(psi) + tr * (std::cos(psi) - 1.0)),
              v_x / w * ((1.0 - std::cos(psi)) + tr * std::sin(psi)), psi);
}

TEST(KinematicOdometry, FrontSteeringFollowsTheAckermannArc) {
  KinematicFactorOptions o;
  KinematicOdometry odo(o, kWheelbase);
  const auto m = DriveCircle(odo, 6.0, 0.2, 5);  // one 0.1 s period
  ASSERT_TRUE(m.has_value());
  EXPECT_EQ(m->t2_ns - m->t1_ns, 100 * kNsPerMillisecond);
  const Vec3 exact = ExactArc(6.0, 0.2, 0.0, 0.1);
  const Vec3 got(m->T_r1_r2.translation().x(), m->T_r1_r2.translation().y(),
                 so3::ToRollPitchYaw(m->T_r1_r2.rotation()).z());
  std::printf("front steering, 0.1 s at 6 m/s: error %.2e m / %.2e rad\n",
              (got - exact).head<2>().norm(), std::abs(got.z() - exact.z()));
  EXPECT_LT((got - exact).head<2>().norm(), 1e-5);
  EXPECT_LT(std::abs(got.z() - exact.z()), 1e-12);
  EXPECT_NEAR(m->distance_m, 0.6, 1e-12);
}

TEST(KinematicOdometry, FourWheelSteeringMovesSidewaysAsTheShuttleDoes) {
  KinematicFactorOptions o;
  o.rear_steering_ratio = 1.0;  // counter-phase, the shuttle
  KinematicOdometry odo(o, 2.8);
  const auto m = DriveCircle(odo, 3.0, 0.3, 5);
  ASSERT_TRUE(m.has_value());
  const double tr = std::tan(-0.3);
  const double w = 3.0 * (std::tan(0.3) - tr) / 2.8;
  const double psi = w * 0.1;
  const Vec2 exact = 3.0 / w * Vec2(std::sin(psi) + tr * (std::cos(psi) - 1.0),
                                    (1.0 - std::cos(psi)) + tr * std::sin(psi));
  EXPECT_LT((m->T_r1_r2.translation().head<2>() - exact).norm(), 1e-5);
  // Twice the yaw of front steering alone, and a lateral displacement at the rear axle.
  EXPECT_NEAR(so3::ToRollPitchYaw(m->T_r1_r2.rotation()).z(), psi, 1e-12);
  EXPECT_LT(m->T_r1_r2.translation().y(), -0.05);
}

TEST(KinematicOdometry, CovarianceGrowsWithDistanceAndStaysFiniteAtStandstill) {
  KinematicFactorOptions o;
  KinematicOdometry moving(o, kWheelbase), still(o, kWheelbase);
  const auto m = DriveCircle(moving, 10.0, 0.05, 5);
  const auto s = DriveCircle(still, 0.0, 0.05, 5);
  ASSERT_TRUE(m && s);
  for (const KinematicMotion* k : {&*m, &*s}) {
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat3>(k->covariance_xy_yaw).eigenvalues().minCoeff(),
              0.0);
    EXPECT_TRUE(k->sqrt_information.allFinite());
  }
  EXPECT_GT(m->covariance_xy_yaw(0, 0), 10.0 * s->covariance_xy_yaw(0, 0));
  // Along-track sigma at 10 m/s over 0.1 s: the per-period scale error of 1 m plus the white
  // speed error of five 20 ms samples.
  EXPECT_NEAR(std::sqrt(m->covariance_xy_yaw(0, 0)),
              std::hypot(o.speed_scale_sigma * 1.0, o.speed_sigma_mps * 0.02 * std::sqrt(5.0)),
              1e-3);
  // Nothing about roll and pitch: those rows of the information are zero.
  const Mat6 info = m->sqrt_information.transpose() * m->sqrt_information;
  const double roll_pitch_rows = info.block<2, 6>(3, 0).norm();
  EXPECT_LT(roll_pitch_rows, 1e-6 * info.norm());
}

TEST(KinematicOdometry, GapRestartsTheIntegration) {
  KinematicFactorOptions o;
  KinematicOdometry odo(o, kWheelbase);
  odo.AddSpeed(0, 5.0);
  odo.AddSpeed(20 * kNsPerMillisecond, 5.0);
  // 0.5 s without a sample: the next one only opens a new interval.
  EXPECT_FALSE(odo.AddSpeed(520 * kNsPerMillisecond, 5.0).has_value());
  std::optional<KinematicMotion> m;
  for (int k = 1; k <= 5; ++k) {
    if (auto r = odo.AddSpeed((520 + 20 * k) * kNsPerMillisecond, 5.0)) m = r;
  }
  ASSERT_TRUE(m.has_value());
  EXPECT_EQ(m->t1_ns, 520 * kNsPerMillisecond);
  EXPECT_NEAR(m->distance_m, 0.5, 1e-12);
}

TEST(KinematicOdometry, RejectsANonPositiveWheelbase) {
  EXPECT_THROW(KinematicOdometry(KinematicFactorOptions{}, 0.0), InputError);
}

}  // namespace
}  // namespace statebench::est
