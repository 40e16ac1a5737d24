// Analytic vehicle-like test trajectory (test fixture): a figure eight with gentle hills, driven
// forward along its tangent (no side slip, no roll), standing still until t_start_s and then
// accelerating smoothly.
//
// Path c(u) = (R sin u, R/2 sin 2u, H sin(u/2)), u(t) = 0 before t_start, then with
// tau = t - t_start:
//   u   = w (tau - T sqrt(pi)/2 erf(tau/T)),  u' = w (1 - exp(-(tau/T)^2)),
//   u'' = w 2 tau / T^2 exp(-(tau/T)^2)
// (speed and acceleration are continuous at the start). Position p = c(u), velocity c' u',
// acceleration c'' u'^2 + c' u''. Attitude R = Rz(yaw) Ry(pitch) with
//   yaw = atan2(c'_y, c'_x),  pitch = atan2(-c'_z, |c'_xy|)     (so3::ToRollPitchYaw convention)
// and body rates (roll = 0) w = (-sin(pitch) yaw', pitch', cos(pitch) yaw').
#pragma once

#include <cmath>
#include <numbers>

#include "core/eigen_types.hpp"
#include "core/so3.hpp"
#include "core/state.hpp"
#include "core/time.hpp"
#include "trajectory_imu.hpp"

namespace statebench::est::testing {

class VehicleTrajectory {
 public:
  static constexpr double kRadius = 40.0, kHill = 2.0, kRate = 0.25, kRamp = 2.0;

  explicit VehicleTrajectory(double t_start_s = 2.0) : t_start_(t_start_s) {}

  // u, u', u''.
  Vec3 Warp(double t) const {
    const double tau = t - t_start_;
    if (tau <= 0.0) return Vec3::Zero();
    const double e = std::exp(-(tau / kRamp) * (tau / kRamp));
    return Vec3(kRate * (tau - kRamp * std::sqrt(std::numbers::pi) / 2 * std::erf(tau / kRamp)),
                kRate * (1.0 - e), kRate * 2.0 * tau / (kRamp * kRamp) * e);
  }
  static Vec3 C(double u) {
    return Vec3(kRadius * std::sin(u), kRadius / 2 * std::sin(2 * u), kHill * std::sin(u / 2));
  }
  static Vec3 C1(double u) {
    return Vec3(kRadius * std::cos(u), kRadius * std::cos(2 * u), kHill / 2 * std::cos(u / 2));
  }
  static Vec3 C2(double u) {
    return Vec3(-kRadius * std::sin(u), -2 * kRadius * std::sin(2 * u),
                -kHill / 4 * std::sin(u / 2));
  }

  Vec3 Position(double t) const { return C(Warp(t).x()); }
  Vec3 Velocity(double t) const {
    const Vec3 w = Warp(t);
    return C1(w.x()) * w.y();
  }
  Vec3 Acceleration(double t) const {
    const Vec3 w = Warp(t);
    return C2(w.x()) * w.y() * w.y() + C1(w.x()) * w.z();
  }
  // (pitch, yaw) and their time derivatives.
  void Angles(double t, double* pitch, double* yaw, double* pitch_rate, double* yaw_rate) const {
    const Vec3 w = Warp(t);
    const Vec3 c1 = C1(w.x()), c2 = C2(w.x());
    const double h = c1.head<2>().norm();
    const double dh = (c1.x() * c2.x() + c1.y() * c2.y()) / h;
    *yaw = std::atan2(c1.y(), c1.x());
    *pitch = std::atan2(-c1.z(), h);
    *yaw_rate = (c1.x() * c2.y() - c1.y() * c2.x()) / (h * h) * w.y();
    *pitch_rate = (h * -c2.z() + c1.z() * dh) / (h * h + c1.z() * c1.z()) * w.y();
  }
  Quat Orientation(double t) const {
    double pitch, yaw, dp, dy;
    Angles(t, &pitch, &yaw, &dp, &dy);
    return so3::FromRollPitchYaw(0.0, pitch, yaw);
  }
  Vec3 Gyro(double t) const {
    double pitch, yaw, dp, dy;
    Angles(t, &pitch, &yaw, &dp, &dy);
    return Vec3(-std::sin(pitch) * dy, dp, std::cos(pitch) * dy);
  }
  Vec3 Accel(double t) const { return SpecificForce(*this, t); }
  NavState State(TimeNs t_ns) const { return StateOf(*this, t_ns); }

 private:
  double t_start_;
};

}  // namespace statebench::est::testing
