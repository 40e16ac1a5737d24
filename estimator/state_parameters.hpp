// Ceres parameter blocks of one navigation state. Block sizes and the manifold each needs:
//   q_world_imu  4  quaternion coefficients (x, y, z, w), RightQuaternionManifold
//   p_world      3  Euclidean (m)
//   v_world      3  Euclidean (m/s)
//   bias         6  Euclidean (gyro rad/s, accel m/s^2), see ImuBias
// Tangent ordering for covariances is that of core/state.hpp: rotation, position, velocity,
// gyro bias, accel bias.
#pragma once

#include <array>

#include "core/eigen_types.hpp"
#include "core/state.hpp"
#include "estimator/imu_bias.hpp"

namespace statebench::est {

struct StateParameters {
  std::array<double, 4> q_world_imu{0.0, 0.0, 0.0, 1.0};
  std::array<double, 3> p_world{};
  std::array<double, 3> v_world{};
  std::array<double, 6> bias{};

  static StateParameters FromNavState(const NavState& s) {
    StateParameters out;
    Eigen::Map<Quat>(out.q_world_imu.data()) = s.q_world_imu.normalized();
    Eigen::Map<Vec3>(out.p_world.data()) = s.p_world;
    Eigen::Map<Vec3>(out.v_world.data()) = s.v_world;
    Eigen::Map<Vec6>(out.bias.data()) << s.gyro_bias, s.accel_bias;
    return out;
  }

  NavState ToNavState(TimeNs t_ns) const {
    NavState s;
    s.t_ns = t_ns;
    s.q_world_imu = Eigen::Map<const Quat>(q_world_imu.data()).normalized();
    s.p_world = Eigen::Map<const Vec3>(p_world.data());
    s.v_world = Eigen::Map<const Vec3>(v_world.data());
    s.gyro_bias = Eigen::Map<const Vec3>(bias.data());
    s.accel_bias = Eigen::Map<const Vec3>(bias.data() + 3);
    return s;
  }
};

}  // namespace statebench::est
