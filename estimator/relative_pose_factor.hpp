// Relative-pose factor between two stamps: lidar odometry (scan to scan) and the kinematic
// factor (rear-axle motion from the encoders) both measure the motion of a sensor frame s rigidly
// mounted on the IMU, T_s1_s2, between t1 and t2.
//
// Each stamp is reached from the latest state at or before it by the IMU (propagated_pose.hpp),
// so the factor sits at the measurement's own stamps, not at the closest states. Prediction:
//   T_s1_s2 = X^-1 T_w_imu(t1)^-1 T_w_imu(t2) X,   X = T_imu_sensor (static extrinsic)
// Residual in the right-perturbation convention of core/se3.hpp, (rho, phi) with
// T_predicted = T_measured Exp(rho, phi) to first order:
//   r = S [ R_m^T (t_pred - t_m) ; Log(R_m^T R_pred) ]
// S (6x6) is a square root of the information of the measurement in the sensor frame; it may be
// rank-deficient (the kinematic factor says nothing about z, roll and pitch): SqrtOfInformation.
//
// Parameter blocks: q, p, v, bias of the anchor of t1 and of the anchor of t2 (8 blocks), or of
// one anchor when both stamps follow the same state (4 blocks). Jacobians by automatic
// differentiation.
//
// Mount correction (MountAxes): the setup's X is measured by hand, so its rotation may be turned
// by a small c (rad, about the sensor frame's own axes): X(c) = (R_x Exp(c), t_x), the lever arm
// as given. Then T_s1_s2 = X(c)^-1 T_imu1_imu2 X(c): the predicted rotation is conjugated by
// Exp(c) and the translation turned by Exp(c)^T (plus the lever arm's share, which does not
// depend on c). The estimated axes of c are scalar blocks after the states (roll, pitch, yaw in
// that order, the others 0), globals of the window; Jacobians by automatic differentiation too.
#pragma once

#include <ceres/cost_function.h>

#include "core/eigen_types.hpp"
#include "core/se3.hpp"
#include "estimator/imu_preintegration.hpp"

namespace statebench::est {

struct RelativePoseMeasurement {
  SE3 T_s1_s2;                          // measured motion of the sensor frame
  SE3 T_imu_sensor;                     // X
  Mat6 sqrt_information = Mat6::Zero();  // (rho, phi) in the sensor frame
};

// Which axes of the mount correction c are estimated (each a scalar block after the states):
// none, pitch and yaw (a vehicle frame whose roll nothing measures), or all three.
struct MountAxes {
  bool roll = false;
  bool pitch = false;
  bool yaw = false;
  int count() const { return int{roll} + int{pitch} + int{yaw}; }
};

// S with S^T S = information for a symmetric positive semi-definite information matrix
// (eigen-decomposition; negative eigenvalues from round-off are clipped to zero).
Mat6 SqrtOfInformation(const Mat6& information);
// Information of a covariance, for convenience; InputError if not positive definite.
Mat6 SqrtInformationOfCovariance(const Mat6& covariance, const char* what);

// The sensor motion predicted from two IMU poses.
SE3 PredictedSensorMotion(const SE3& T_w_imu1, const SE3& T_w_imu2, const SE3& T_imu_sensor);

// The whitened residual for given IMU poses (used by tests and to check final residuals).
Vec6 RelativePoseResidual(const RelativePoseMeasurement& m, const SE3& T_w_imu1,
                          const SE3& T_w_imu2);

// Anchors a (for t1) and b (for t2) distinct; to_t1 covers [t_a, t1], to_t2 [t_b, t2]. With
// mount axes, their corrections are blocks 9.. (InputError for roll without pitch and yaw, or
// one axis alone: combinations nothing uses).
ceres::CostFunction* CreateRelativePoseFactor(const RelativePoseMeasurement& m,
                                              const ImuPreintegration& to_t1,
                                              const ImuPreintegration& to_t2,
                                              const MountAxes& mount = {});
// Both stamps after the same anchor: to_t1 covers [t_a, t1], to_t2 [t_a, t2]. Mount corrections
// are blocks 5..
ceres::CostFunction* CreateRelativePoseFactorOneAnchor(const RelativePoseMeasurement& m,
                                                       const ImuPreintegration& to_t1,
                                                       const ImuPreintegration& to_t2,
                                                       const MountAxes& mount = {});

}  // namespace statebench::est
