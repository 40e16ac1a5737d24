#include "simulator/body_kinematics.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/so3.hpp"

namespace statebench::sim {
namespace {

// A hilly terrain with grade and cross slope everywhere.
Terrain Hills() {
  std::vector<Vec3> points;
  for (double x = -100; x <= 100; x += 4) {
    for (double y = -100; y <= 100; y += 4) {
      points.emplace_back(x, y,
                          0.04 * x - 0.03 * y + 3.0 * std::sin(x / 25.0) * std::cos(y / 30.0));
    }
  }
  return Terrain::Fit(points);
}

// Analytic planar motion: position, yaw and their derivatives; u, w are the heading-frame
// components of the horizontal velocity, and (u', w') follow from the acceleration:
// a_u = u' - r w, a_w = w' + r u.
struct Motion {
  static Vec2 P(double t) { return Vec2(6 * t - 0.1 * t * t, 10 * std::sin(0.3 * t)); }
  static Vec2 V(double t) { return Vec2(6 - 0.2 * t, 3 * std::cos(0.3 * t)); }
  static Vec2 Acc(double t) { return Vec2(-0.2, -0.9 * std::sin(0.3 * t)); }
  static double Yaw(double t) { return 0.2 + 0.4 * std::sin(0.5 * t); }
  static double YawRate(double t) { return 0.2 * std::cos(0.5 * t); }
  static double YawAcc(double t) { return -0.1 * std::sin(0.5 * t); }

  static void At(double t, VehicleState* x, VehicleState* dx) {
    const double c = std::cos(Yaw(t));
    const double s = std::sin(Yaw(t));
    const Vec2 v = V(t);
    const Vec2 a = Acc(t);
    *x = VehicleState{};
    x->x_m = P(t).x();
    x->y_m = P(t).y();
    x->yaw_rad = Yaw(t);
    x->u_mps = c * v.x() + s * v.y();
    x->w_mps = -s * v.x() + c * v.y();
    x->yaw_rate_radps = YawRate(t);
    *dx = VehicleState{};
    dx->x_m = v.x();
    dx->y_m = v.y();
    dx->yaw_rad = YawRate(t);
    dx->u_mps = c * a.x() + s * a.y() + x->yaw_rate_radps * x->w_mps;
    dx->w_mps = -s * a.x() + c * a.y() - x->yaw_rate_radps * x->u_mps;
    dx->yaw_rate_radps = YawAcc(t);
  }
};

FrameKinematics KinematicsAt(const Terrain& terrain, double t) {
  VehicleState x;
  VehicleState dx;
  Motion::At(t, &x, &dx);
  return BodyKinematics(terrain, x, dx);
}

TEST(BodyKinematics, RatesAreTheDerivativesOfThePose) {
  const Terrain terrain = Hills();
  const double e = 1e-4;
  for (double t : {0.5, 3.0, 7.7, 12.0}) {
    const FrameKinematics k = KinematicsAt(terrain, t);
    const FrameKinematics k0 = KinematicsAt(terrain, t - e);
    const FrameKinematics k1 = KinematicsAt(terrain, t + e);
    // Body on the road, z along the normal, yaw of the body = planar yaw.
    const Vec3 p = k.T_world_frame.translation();
    EXPECT_NEAR(p.z(), terrain.Height(p.x(), p.y()), 1e-12);
    EXPECT_NEAR((k.T_world_frame.rotation() * Vec3::UnitZ() - terrain.Normal(p.x(), p.y())).norm(),
                0.0, 1e-12);
    EXPECT_NEAR(so3::ToRollPitchYaw(k.T_world_frame.rotation()).z(), Motion::Yaw(t), 1e-12);
    // Velocity, acceleration, angular rate and acceleration against central differences.
    const Vec3 v_fd = (k1.T_world_frame.translation() - k0.T_world_frame.translation()) / (2 * e);
    EXPECT_LT((v_fd - k.v_world).norm(), 1e-7) << t;
    EXPECT_LT(((k1.v_world - k0.v_world) / (2 * e) - k.a_world).norm(), 1e-7) << t;
    const Vec3 omega_fd =
        so3::Log(k0.T_world_frame.rotation().conjugate() * k1.T_world_frame.rotation()) / (2 * e);
    EXPECT_LT((omega_fd - k.omega_frame).norm(), 1e-7) << t;
    EXPECT_LT(((k1.omega_frame - k0.omega_frame) / (2 * e) - k.alpha_frame).norm(), 1e-7) << t;
    // A real hill: pitch and roll rates are not trivially zero.
    EXPECT_GT(k.omega_frame.head<2>().norm(), 1e-3);
  }
}

TEST(BodyKinematics, FlatGroundIsPlanar) {
  const Terrain flat(3.0);
  const FrameKinematics k = KinematicsAt(flat, 2.0);
  EXPECT_EQ(k.T_world_frame.translation().z(), 3.0);
  EXPECT_NEAR(k.omega_frame.head<2>().norm(), 0.0, 1e-15);
  EXPECT_NEAR(k.omega_frame.z(), Motion::YawRate(2.0), 1e-15);
  EXPECT_NEAR(k.alpha_frame.z(), Motion::YawAcc(2.0), 1e-15);
  EXPECT_EQ(k.v_world.z(), 0.0);
  EXPECT_EQ(k.a_world.z(), 0.0);
}

}  // namespace
}  // namespace statebench::sim
