#include "estimator/body_velocity_factor.hpp"

#include <ceres/autodiff_cost_function.h>

#include "estimator/propagated_pose.hpp"

namespace statebench::est {
namespace {

template <typename T>
Eigen::Matrix<T, 3, 1> Velocity(const BodyVelocityMeasurement& m, const Eigen::Quaternion<T>& q,
                                const Eigen::Matrix<T, 3, 1>& v_world,
                                const Eigen::Matrix<T, 3, 1>& gyro_bias) {
  const Eigen::Matrix<T, 3, 1> omega = m.gyro_raw.cast<T>() - gyro_bias;
  const Eigen::Matrix<T, 3, 1> v_imu =
      q.conjugate() * v_world + omega.cross(m.p_imu_point.cast<T>());
  if (m.frame == BodyVelocityMeasurement::Frame::kWorld) return q * v_imu;
  return m.q_imu_frame.conjugate().cast<T>() * v_imu;
}

struct Functor {
  BodyVelocityMeasurement m;
  PropagationDeltas d;

  template <typename T>
  bool operator()(const T* q, const T* v, const T* bias, T* residual) const {
    // p does not enter the velocity: any value serves the propagation.
    const T p[3] = {T(0.0), T(0.0), T(0.0)};
    const PropagatedPose<T> x = Propagate(d, q, p, v, bias);
    const Eigen::Matrix<T, 3, 1> bg = Eigen::Map<const Eigen::Matrix<T, 3, 1>>(bias);
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = m.sqrt_information.cast<T>() * (Velocity(m, x.q_world_imu, x.v_world, bg) -
                                        m.v_frame.cast<T>());
    return true;
  }
};

}  // namespace

Vec3 PointVelocity(const BodyVelocityMeasurement& m, const Quat& q_world_imu,
                   const Vec3& v_world, const Vec3& gyro_bias) {
  return Velocity<double>(m, q_world_imu, v_world, gyro_bias);
}

ceres::CostFunction* CreateBodyVelocityFactor(const BodyVelocityMeasurement& m,
                                              const ImuPreintegration& propagation) {
  return new ceres::AutoDiffCostFunction<Functor, 3, 4, 3, 6>(
      new Functor{m, PropagationDeltas::From(propagation)});
}

}  // namespace statebench::est
