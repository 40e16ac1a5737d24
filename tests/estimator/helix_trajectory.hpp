// Analytic 3D test trajectory with closed-form pose and derivatives (test fixture).
//
// Position: a climbing helix with a wavy height, radius 20 m, 0.5 rad/s (10 m/s):
//   p(t) = (r cos wt, r sin wt, c t + d sin(u t))
// Attitude: R = Rz(yaw) Ry(pitch) Rx(roll) with yaw along the tangent plus oscillating
// roll and pitch, so every gyro axis and the specific force vary in time. Body rates from the
// Z-Y-X Euler rates:
//   w = (roll' - sin(pitch) yaw',
//        cos(roll) pitch' + sin(roll) cos(pitch) yaw',
//        -sin(roll) pitch' + cos(roll) cos(pitch) yaw').
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "core/so3.hpp"
#include "core/state.hpp"
#include "core/time.hpp"
#include "trajectory_imu.hpp"

namespace statebench::est::testing {

class HelixTrajectory {
 public:
  static constexpr double kRadius = 20.0, kRate = 0.5, kClimb = 0.5, kWaveAmp = 0.3,
                          kWaveRate = 0.9;

  Vec3 Position(double t) const {
    return Vec3(kRadius * std::cos(kRate * t), kRadius * std::sin(kRate * t),
                kClimb * t + kWaveAmp * std::sin(kWaveRate * t));
  }
  Vec3 Velocity(double t) const {
    return Vec3(-kRadius * kRate * std::sin(kRate * t), kRadius * kRate * std::cos(kRate * t),
                kClimb + kWaveAmp * kWaveRate * std::cos(kWaveRate * t));
  }
  Vec3 Acceleration(double t) const {
    const double w2 = kRate * kRate;
    return Vec3(-kRadius * w2 * std::cos(kRate * t), -kRadius * w2 * std::sin(kRate * t),
                -kWaveAmp * kWaveRate * kWaveRate * std::sin(kWaveRate * t));
  }
  // (roll, pitch, yaw) and their time derivatives.
  Vec3 Euler(double t) const {
    return Vec3(0.2 * std::sin(0.7 * t + 0.3), 0.1 * std::sin(1.3 * t),
                kRate * t + std::numbers::pi / 2 + 0.05 * std::sin(2.1 * t));
  }
  Vec3 EulerRate(double t) const {
    return Vec3(0.2 * 0.7 * std::cos(0.7 * t + 0.3), 0.1 * 1.3 * std::cos(1.3 * t),
                kRate + 0.05 * 2.1 * std::cos(2.1 * t));
  }
  Quat Orientation(double t) const {
    const Vec3 e = Euler(t);
    return so3::FromRollPitchYaw(e.x(), e.y(), e.z());
  }
  Vec3 Gyro(double t) const {
    const Vec3 e = Euler(t);
    const Vec3 d = EulerRate(t);
    const double sr = std::sin(e.x()), cr = std::cos(e.x());
    const double sp = std::sin(e.y()), cp = std::cos(e.y());
    return Vec3(d.x() - sp * d.z(), cr * d.y() + sr * cp * d.z(), -sr * d.y() + cr * cp * d.z());
  }
  // Specific force in the IMU frame: R^T (a - g).
  Vec3 Accel(double t) const { return SpecificForce(*this, t); }

  NavState State(TimeNs t_ns) const { return StateOf(*this, t_ns); }
};

// x moved off by draws of r3 (a standard normal Vec3), where the factors' Jacobian tests
// linearise: rotation by 0.1 rad (right), position and velocity by 1 m and 1 m/s, the gyro and
// accelerometer biases drawn at 0.01 rad/s and 0.1 m/s^2.
template <typename Draw>
NavState PerturbedState(NavState x, Draw& r3) {
  x.q_world_imu = x.q_world_imu * so3::Exp<double>(0.1 * r3());
  x.p_world += r3();
  x.v_world += r3();
  x.gyro_bias = 0.01 * r3();
  x.accel_bias = 0.1 * r3();
  return x;
}

// 100 Hz samples of the helix over [0, 3] s, with a constant sensor bias (gyro, accel) added.
inline std::vector<ImuSample> HelixSamples(const Vec3& gyro_bias = Vec3::Zero(),
                                           const Vec3& accel_bias = Vec3::Zero()) {
  const HelixTrajectory helix;
  std::vector<ImuSample> samples;
  for (int k = 0; k <= 300; ++k) {
    samples.push_back(SampleOf(helix, k * 10 * kNsPerMillisecond, gyro_bias, accel_bias));
  }
  return samples;
}

}  // namespace statebench::est::testing
