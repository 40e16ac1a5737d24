#include "estimator/body_velocity_factor.hpp"

#include <ceres/sized_cost_function.h>

#include "core/error.hpp"
#include "core/so3.hpp"
#include "estimator/propagated_pose.hpp"
#include "estimator/so3_manifold.hpp"

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

// The point's velocity at the propagated state, in the frame the setup gives (kVehicle) or in
// the world (kWorld), with its analytic Jacobians before the quaternion's minus Jacobian (the
// derivation is in the header). theta: the right perturbation of q_i.
struct PointVelocityLinearization {
  Vec3 velocity;
  Mat3 J_theta, J_v, J_bg, J_ba;
};

PointVelocityLinearization LinearizePointVelocity(const BodyVelocityMeasurement& m,
                                                  const PropagationDeltas& d,
                                                  double const* const* parameters,
                                                  bool with_jacobians) {
  // p does not enter the velocity: any value serves the propagation.
  const double p[3] = {0.0, 0.0, 0.0};
  const PropagatedPose<double> x = Propagate(d, parameters[0], p, parameters[1], parameters[2]);
  const Eigen::Map<const Vec3> bg(parameters[2]);
  PointVelocityLinearization out;
  out.velocity = Velocity(m, x.q_world_imu, x.v_world, Vec3(bg));
  if (!with_jacobians) return out;

  const Eigen::Map<const Quat> q_i(parameters[0]);
  const Eigen::Map<const Vec3> v_i(parameters[1]);
  const Mat3 R_i = q_i.toRotationMatrix();
  const Vec3 dbg = bg - d.bg_lin;
  const Vec3 dba = Eigen::Map<const Vec3>(parameters[2] + 3) - d.ba_lin;
  const Vec3 phi = d.J_R_bg * dbg;
  const Mat3 E = (d.dq * so3::Exp<double>(phi)).toRotationMatrix();  // dR(bg)
  const Mat3 R_t = R_i * E;
  const Vec3 dv = d.dv + d.J_v_bg * dbg + d.J_v_ba * dba;
  const Mat3 J_eps_bg = so3::RightJacobian(phi) * d.J_R_bg;  // dR(bg + d) = dR(bg) Exp(J d)
  const Mat3 hat_p = so3::Hat<double>(m.p_imu_point);
  if (m.frame == BodyVelocityMeasurement::Frame::kWorld) {
    const Vec3 c = (m.gyro_raw - bg).cross(m.p_imu_point);
    out.J_theta = -R_i * so3::Hat<double>(dv + E * c);
    out.J_v = Mat3::Identity();
    out.J_bg = R_i * d.J_v_bg - R_t * so3::Hat<double>(c) * J_eps_bg + R_t * hat_p;
    out.J_ba = R_i * d.J_v_ba;
  } else {
    const Mat3 S_frame = m.q_imu_frame.conjugate().toRotationMatrix();
    const Vec3 a = R_i.transpose() * (v_i + kGravityWorld * d.tau_s);
    const Vec3 u = E.transpose() * (a + dv);  // R_t^T v_t
    out.J_theta = S_frame * E.transpose() * so3::Hat<double>(a);
    out.J_v = S_frame * R_t.transpose();
    out.J_bg = S_frame * (so3::Hat<double>(u) * J_eps_bg + E.transpose() * d.J_v_bg + hat_p);
    out.J_ba = S_frame * E.transpose() * d.J_v_ba;
  }
  return out;
}

using RowMajor3x3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
using RowMajor3x4 = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;
using RowMajor3x6 = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;

// The state blocks' Jacobians of r = A v - ..., for a 3x3 A (S, or S times the mount correction).
void WriteStateJacobians(const Mat3& A, const PointVelocityLinearization& l,
                         double const* const* parameters, double** jacobians) {
  if (jacobians[0] != nullptr) {
    Eigen::Map<RowMajor3x4>{jacobians[0]} = A * l.J_theta * QuaternionMinusJacobian(parameters[0]);
  }
  if (jacobians[1] != nullptr) Eigen::Map<RowMajor3x3>{jacobians[1]} = A * l.J_v;
  if (jacobians[2] != nullptr) {
    RowMajor3x6 J;
    J.leftCols<3>() = A * l.J_bg;
    J.rightCols<3>() = A * l.J_ba;
    Eigen::Map<RowMajor3x6>{jacobians[2]} = J;
  }
}

// r = S (v_c - v_measured).
class BodyVelocityCost final : public ceres::SizedCostFunction<3, 4, 3, 6> {
 public:
  BodyVelocityCost(const BodyVelocityMeasurement& m, const ImuPreintegration& propagation)
      : m_(m), d_(PropagationDeltas::From(propagation)) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const PointVelocityLinearization l =
        LinearizePointVelocity(m_, d_, parameters, jacobians != nullptr);
    Eigen::Map<Vec3>{residuals} = m_.sqrt_information * (l.velocity - m_.v_frame);
    if (jacobians != nullptr) WriteStateJacobians(m_.sqrt_information, l, parameters, jacobians);
    return true;
  }

 private:
  const BodyVelocityMeasurement m_;
  const PropagationDeltas d_;
};

// The vehicle frame turned by c = (0, c_pitch, c_yaw) from the one the setup gives:
// r = S (Exp(c)^T v_c - v_measured), with d/dc = Exp(-c) [v_c]x Jr(-c) (columns y, z).
class MountCorrectedBodyVelocityCost final : public ceres::SizedCostFunction<3, 4, 3, 6, 1, 1> {
 public:
  MountCorrectedBodyVelocityCost(const BodyVelocityMeasurement& m,
                                 const ImuPreintegration& propagation)
      : m_(m), d_(PropagationDeltas::From(propagation)) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const PointVelocityLinearization l =
        LinearizePointVelocity(m_, d_, parameters, jacobians != nullptr);
    const Vec3 c(0.0, parameters[3][0], parameters[4][0]);
    const Mat3 C = so3::Exp<double>(c).conjugate().toRotationMatrix();
    Eigen::Map<Vec3>{residuals} = m_.sqrt_information * (C * l.velocity - m_.v_frame);
    if (jacobians == nullptr) return true;
    const Mat3 SC = m_.sqrt_information * C;
    WriteStateJacobians(SC, l, parameters, jacobians);
    const Mat3 J_c = SC * so3::Hat<double>(l.velocity) * so3::RightJacobian(-c);
    if (jacobians[3] != nullptr) Eigen::Map<Vec3>{jacobians[3]} = J_c.col(1);
    if (jacobians[4] != nullptr) Eigen::Map<Vec3>{jacobians[4]} = J_c.col(2);
    return true;
  }

 private:
  const BodyVelocityMeasurement m_;
  const PropagationDeltas d_;
};

}  // namespace

Vec3 PointVelocity(const BodyVelocityMeasurement& m, const Quat& q_world_imu,
                   const Vec3& v_world, const Vec3& gyro_bias) {
  return Velocity<double>(m, q_world_imu, v_world, gyro_bias);
}

ceres::CostFunction* CreateBodyVelocityFactor(const BodyVelocityMeasurement& m,
                                              const ImuPreintegration& propagation) {
  return new BodyVelocityCost(m, propagation);
}

ceres::CostFunction* CreateMountCorrectedBodyVelocityFactor(const BodyVelocityMeasurement& m,
                                                            const ImuPreintegration& propagation) {
  if (m.frame != BodyVelocityMeasurement::Frame::kVehicle) {
    throw InputError("body velocity: a mount correction needs a vehicle-frame measurement");
  }
  return new MountCorrectedBodyVelocityCost(m, propagation);
}

}  // namespace statebench::est
