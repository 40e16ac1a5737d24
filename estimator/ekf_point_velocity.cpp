#include "estimator/ekf_point_velocity.hpp"

namespace statebench::est::ekf {

PointVelocity PredictPointVelocity(const VecN& x, const Mat3& R_body_sensor,
                                   const Vec3& p_body_point) {
  const Vec3 v_point_body(x[kVx] - x[kR] * p_body_point.y(), x[kVy] + x[kR] * p_body_point.x(),
                          0.0);
  const Mat3 R_sensor_body = R_body_sensor.transpose();
  PointVelocity out;
  out.v_sensor = R_sensor_body * v_point_body;
  out.H.col(kVx) = R_sensor_body.col(0);
  out.H.col(kVy) = R_sensor_body.col(1);
  out.H.col(kR) = R_sensor_body * Vec3(-p_body_point.y(), p_body_point.x(), 0.0);
  return out;
}

}  // namespace statebench::est::ekf
