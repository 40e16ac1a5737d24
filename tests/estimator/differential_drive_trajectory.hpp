// Analytic drive of a differential-drive robot on flat ground (test fixture): straight legs and
// turns on the spot, each with the smooth profile
//   sigma(tau) = tau - sin(2 pi tau) / (2 pi),  sigma' = 1 - cos(2 pi tau),
//   sigma'' = 2 pi sin(2 pi tau),               tau = (t - t_start) / T in [0, 1],
// so speed, yaw rate and both accelerations are continuous and zero at each leg's ends (peak
// speed 2 L / T). A leg of length L in T: arc length s = L sigma; a turn by angle A in T:
// yaw = yaw_0 + A sigma; a pause: nothing moves.
//
// The body frame is the robot's base_link (the wheel axle's centre, FLU, on the ground): its
// velocity is (s', 0, 0), so wheel odometry measures exactly that. The IMU is mounted at
// (p_body_imu, R_body_imu); the trajectory type of trajectory_imu.hpp is the IMU's:
//   R_world_imu = Rz(yaw) R_body_imu,  p_imu = c + Rz(yaw) p_body_imu,
//   v_imu = c' + yaw' z x (Rz p_body_imu),  a_imu = c'' + yaw'' z x r + yaw'^2 z x (z x r),
//   omega_imu = R_body_imu^T (0, 0, yaw').
#pragma once

#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/state.hpp"
#include "core/time.hpp"
#include "trajectory_imu.hpp"

namespace statebench::est::testing {

class DifferentialDriveTrajectory {
 public:
  struct Leg {
    double duration_s = 0.0;
    double length_m = 0.0;  // a straight leg
    double turn_rad = 0.0;  // a turn on the spot (left positive)
  };

  DifferentialDriveTrajectory(std::vector<Leg> legs, const Vec3& p_body_imu, const Quat& q_body_imu)
      : legs_(std::move(legs)), p_body_imu_(p_body_imu), q_body_imu_(q_body_imu) {
    Vec2 c = Vec2::Zero();
    double yaw = 0.0, t = 0.0;
    for (const Leg& leg : legs_) {
      starts_.push_back({t, c, yaw});
      t += leg.duration_s;
      c += leg.length_m * Vec2(std::cos(yaw), std::sin(yaw));
      yaw += leg.turn_rad;
    }
    starts_.push_back({t, c, yaw});
  }

  double duration_s() const { return starts_.back().t; }
  double distance_m() const {
    double d = 0.0;
    for (const Leg& leg : legs_) d += leg.length_m;
    return d;
  }

  // Body (base_link) pose and its first and second derivatives at t.
  struct Body {
    Vec2 c = Vec2::Zero(), c1 = Vec2::Zero(), c2 = Vec2::Zero();
    double yaw = 0.0, yaw1 = 0.0, yaw2 = 0.0;
    double speed = 0.0;  // s'
  };
  Body BodyAt(double t) const {
    std::size_t k = 0;
    while (k + 1 < legs_.size() && t >= starts_[k + 1].t) ++k;
    const Start& s = starts_[k];
    Body b;
    b.c = s.c;
    b.yaw = s.yaw;
    if (t < s.t || t >= starts_[k + 1].t) {  // before the first leg or after the last one
      if (t >= starts_[k + 1].t) {
        b.c = starts_[k + 1].c;
        b.yaw = starts_[k + 1].yaw;
      }
      return b;
    }
    const Leg& leg = legs_[k];
    const double T = leg.duration_s;
    const double tau = (t - s.t) / T;
    const double w = 2.0 * std::numbers::pi;
    const double sigma = tau - std::sin(w * tau) / w;
    const double sigma1 = (1.0 - std::cos(w * tau)) / T;
    const double sigma2 = w * std::sin(w * tau) / (T * T);
    const Vec2 dir(std::cos(s.yaw), std::sin(s.yaw));
    b.c = s.c + leg.length_m * sigma * dir;
    b.speed = leg.length_m * sigma1;
    b.c1 = b.speed * dir;
    b.c2 = leg.length_m * sigma2 * dir;
    b.yaw = s.yaw + leg.turn_rad * sigma;
    b.yaw1 = leg.turn_rad * sigma1;
    b.yaw2 = leg.turn_rad * sigma2;
    return b;
  }

  // The IMU's trajectory (trajectory_imu.hpp).
  Quat Orientation(double t) const {
    return Quat(Eigen::AngleAxisd(BodyAt(t).yaw, Vec3::UnitZ())) * q_body_imu_;
  }
  Vec3 Position(double t) const {
    const Body b = BodyAt(t);
    return Vec3(b.c.x(), b.c.y(), 0.0) + Eigen::AngleAxisd(b.yaw, Vec3::UnitZ()) * p_body_imu_;
  }
  Vec3 Velocity(double t) const {
    const Body b = BodyAt(t);
    const Vec3 r = Eigen::AngleAxisd(b.yaw, Vec3::UnitZ()) * p_body_imu_;
    return Vec3(b.c1.x(), b.c1.y(), 0.0) + b.yaw1 * Vec3::UnitZ().cross(r);
  }
  Vec3 Acceleration(double t) const {
    const Body b = BodyAt(t);
    const Vec3 r = Eigen::AngleAxisd(b.yaw, Vec3::UnitZ()) * p_body_imu_;
    const Vec3 z = Vec3::UnitZ();
    return Vec3(b.c2.x(), b.c2.y(), 0.0) + b.yaw2 * z.cross(r) +
           b.yaw1 * b.yaw1 * z.cross(z.cross(r));
  }
  Vec3 Gyro(double t) const { return q_body_imu_.conjugate() * Vec3(0.0, 0.0, BodyAt(t).yaw1); }
  Vec3 Accel(double t) const { return SpecificForce(*this, t); }
  NavState State(TimeNs t_ns) const { return StateOf(*this, t_ns); }

 private:
  struct Start {
    double t = 0.0;
    Vec2 c = Vec2::Zero();
    double yaw = 0.0;
  };
  std::vector<Leg> legs_;
  Vec3 p_body_imu_;
  Quat q_body_imu_;
  std::vector<Start> starts_;
};

}  // namespace statebench::est::testing
