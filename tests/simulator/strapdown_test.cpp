// The strapdown integrator lives in core/; its test sits here because tests/core is not globbed.
#include "core/strapdown.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/so3.hpp"
#include "core/state.hpp"

namespace statebench {
namespace {

// Analytic trajectory: p(t) a smooth 3D curve, R(t) = Rz(psi(t)) Exp(phi(t)) with a full
// yaw rotation every ~21 s and small roll/pitch oscillations. Exact rates:
//   omega_body = Exp(phi)^T (0, 0, psi') + Jr(phi) phi',   f = R^T (p'' - g).
struct Analytic {
  static Vec3 Position(double t) {
    return Vec3(20 * std::sin(0.2 * t), 15 * (1 - std::cos(0.3 * t)), 2 * std::sin(0.1 * t));
  }
  static Vec3 Velocity(double t) {
    return Vec3(4 * std::cos(0.2 * t), 4.5 * std::sin(0.3 * t), 0.2 * std::cos(0.1 * t));
  }
  static Vec3 Acceleration(double t) {
    return Vec3(-0.8 * std::sin(0.2 * t), 1.35 * std::cos(0.3 * t), -0.02 * std::sin(0.1 * t));
  }
  static Vec3 Phi(double t) { return Vec3(0.1 * std::sin(0.5 * t), 0.05 * std::cos(0.7 * t), 0.0); }
  static Vec3 PhiDot(double t) {
    return Vec3(0.05 * std::cos(0.5 * t), -0.035 * std::sin(0.7 * t), 0.0);
  }
  static double Yaw(double t) { return 0.3 * t; }
  static Quat Rotation(double t) {
    return Quat(Eigen::AngleAxisd(Yaw(t), Vec3::UnitZ())) * so3::Exp(Phi(t));
  }
  static InertialRates Rates(double t) {
    InertialRates r;
    r.omega_body =
        so3::Exp(Phi(t)).conjugate() * Vec3(0, 0, 0.3) + so3::RightJacobian(Phi(t)) * PhiDot(t);
    r.specific_force_body = Rotation(t).conjugate() * (Acceleration(t) - kGravityWorld);
    return r;
  }
};

struct Errors {
  double position_m;
  double rotation_rad;
};

Errors Integrate(double duration_s, double dt_s) {
  const int n = static_cast<int>(std::lround(duration_s / dt_s)) + 1;
  std::vector<InertialRates> samples;
  for (int k = 0; k < n; ++k) samples.push_back(Analytic::Rates(k * dt_s));
  StrapdownState x0{Analytic::Rotation(0.0), Analytic::Position(0.0), Analytic::Velocity(0.0)};
  const std::vector<StrapdownState> out = IntegrateStrapdown(x0, samples, dt_s);
  const double t = (n - 1) * dt_s;
  return {(out.back().p_world - Analytic::Position(t)).norm(),
          so3::Log(Analytic::Rotation(t).conjugate() * out.back().q_world_body).norm()};
}

TEST(Strapdown, ReproducesAnAnalyticTrajectory) {
  const Errors e = Integrate(60.0, 1e-3);
  RecordProperty("position_error_m", std::to_string(e.position_m));
  EXPECT_LT(e.position_m, 1e-6);
  EXPECT_LT(e.rotation_rad, 1e-9);
}

TEST(Strapdown, IsFourthOrder) {
  const Errors coarse = Integrate(20.0, 0.04);
  const Errors fine = Integrate(20.0, 0.02);
  // Halving the step divides the error by ~16 for a 4th-order scheme (8 would be 3rd order).
  EXPECT_GT(coarse.position_m / fine.position_m, 12.0);
  EXPECT_GT(coarse.rotation_rad / fine.rotation_rad, 12.0);
}

TEST(Strapdown, StandingStillStaysStill) {
  std::vector<InertialRates> samples(1000);
  for (auto& s : samples) s.specific_force_body = -kGravityWorld;
  const auto out = IntegrateStrapdown(StrapdownState{}, samples, 1e-3);
  EXPECT_EQ(out.size(), samples.size());
  EXPECT_LT(out.back().p_world.norm(), 1e-12);
  EXPECT_LT(out.back().v_world.norm(), 1e-12);
}

}  // namespace
}  // namespace statebench
