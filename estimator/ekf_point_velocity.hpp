// The EKF's odometry measurement model: the velocity of a point of the planar vehicle (a speed
// encoder's wheel, a body_velocity sensor's origin) in a frame fixed to the vehicle.
//
// With the single-track state (ekf_single_track_model.hpp: vx, vy the body-frame velocity of
// the body origin, r the yaw rate) the point at p (body frame) moves with
//   v_point_body = (vx - r p_y, vy + r p_x, 0)
// (planar: no vertical velocity in the body frame, no roll or pitch rate), seen in the sensor
// frame rotated R_body_sensor from the body frame as
//   v_sensor = R_body_sensor^T v_point_body.
// Linear in the state: H = dv_sensor/dx has the columns
//   kVx: R^T e_x,  kVy: R^T e_y,  kR: R^T (-p_y, p_x, 0),  every other column 0.
#pragma once

#include "core/eigen_types.hpp"
#include "estimator/ekf_single_track_model.hpp"

namespace statebench::est::ekf {

struct PointVelocity {
  Vec3 v_sensor = Vec3::Zero();  // m/s, sensor frame
  Eigen::Matrix<double, 3, kN> H = Eigen::Matrix<double, 3, kN>::Zero();
};

PointVelocity PredictPointVelocity(const VecN& x, const Mat3& R_body_sensor,
                                   const Vec3& p_body_point);

}  // namespace statebench::est::ekf
