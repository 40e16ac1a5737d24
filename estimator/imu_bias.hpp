// IMU biases in the IMU frame. In Ceres they live in one 6-vector parameter block ordered
// (gyro, accel), the order of the 15x15 state covariance (core/state.hpp).
#pragma once

#include "core/eigen_types.hpp"

namespace statebench::est {

struct ImuBias {
  Vec3 gyro = Vec3::Zero();   // rad/s
  Vec3 accel = Vec3::Zero();  // m/s^2

  Vec6 AsVector() const {
    Vec6 b;
    b << gyro, accel;
    return b;
  }
  static ImuBias FromVector(const Vec6& b) { return ImuBias{b.head<3>(), b.tail<3>()}; }
};

}  // namespace statebench::est
