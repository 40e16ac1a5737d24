#include "estimator/body_velocity_factor.hpp"

#include <ceres/sized_cost_function.h>

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

// The residual as Velocity gives it at the propagated state, with analytic Jacobians (the
// derivation is in the header). theta: the right perturbation of q_i.
class BodyVelocityCost final : public ceres::SizedCostFunction<3, 4, 3, 6> {
 public:
  BodyVelocityCost(const BodyVelocityMeasurement& m, const ImuPreintegration& propagation)
      : m_(m), d_(PropagationDeltas::From(propagation)) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    // p does not enter the velocity: any value serves the propagation.
    const double p[3] = {0.0, 0.0, 0.0};
    const PropagatedPose<double> x = Propagate(d_, parameters[0], p, parameters[1], parameters[2]);
    const Eigen::Map<const Vec3> bg(parameters[2]);
    Eigen::Map<Vec3>{residuals} =
        m_.sqrt_information * (Velocity(m_, x.q_world_imu, x.v_world, Vec3(bg)) - m_.v_frame);
    if (jacobians == nullptr) return true;

    const Eigen::Map<const Quat> q_i(parameters[0]);
    const Eigen::Map<const Vec3> v_i(parameters[1]);
    const Mat3 R_i = q_i.toRotationMatrix();
    const Vec3 dbg = bg - d_.bg_lin;
    const Vec3 dba = Eigen::Map<const Vec3>(parameters[2] + 3) - d_.ba_lin;
    const Vec3 phi = d_.J_R_bg * dbg;
    const Mat3 E = (d_.dq * so3::Exp<double>(phi)).toRotationMatrix();  // dR(bg)
    const Mat3 R_t = R_i * E;
    const Vec3 dv = d_.dv + d_.J_v_bg * dbg + d_.J_v_ba * dba;
    const Mat3 J_eps_bg = so3::RightJacobian(phi) * d_.J_R_bg;  // dR(bg + d) = dR(bg) Exp(J d)
    const Mat3 hat_p = so3::Hat<double>(m_.p_imu_point);
    Mat3 J_theta, J_v, J_bg, J_ba;  // of the point's velocity before the measurement frame
    if (m_.frame == BodyVelocityMeasurement::Frame::kWorld) {
      const Vec3 c = (m_.gyro_raw - bg).cross(m_.p_imu_point);
      J_theta = -R_i * so3::Hat<double>(dv + E * c);
      J_v = Mat3::Identity();
      J_bg = R_i * d_.J_v_bg - R_t * so3::Hat<double>(c) * J_eps_bg + R_t * hat_p;
      J_ba = R_i * d_.J_v_ba;
    } else {
      const Mat3 S_frame = m_.q_imu_frame.conjugate().toRotationMatrix();
      const Vec3 a = R_i.transpose() * (v_i + kGravityWorld * d_.tau_s);
      const Vec3 u = E.transpose() * (a + dv);  // R_t^T v_t
      J_theta = S_frame * E.transpose() * so3::Hat<double>(a);
      J_v = S_frame * R_t.transpose();
      J_bg = S_frame * (so3::Hat<double>(u) * J_eps_bg + E.transpose() * d_.J_v_bg + hat_p);
      J_ba = S_frame * E.transpose() * d_.J_v_ba;
    }
    using RowMajor3x3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
    using RowMajor3x4 = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;
    using RowMajor3x6 = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;
    const Mat3& S = m_.sqrt_information;
    if (jacobians[0] != nullptr) {
      Eigen::Map<RowMajor3x4>{jacobians[0]} =
          S * J_theta * QuaternionMinusJacobian(parameters[0]);
    }
    if (jacobians[1] != nullptr) Eigen::Map<RowMajor3x3>{jacobians[1]} = S * J_v;
    if (jacobians[2] != nullptr) {
      RowMajor3x6 J;
      J.leftCols<3>() = S * J_bg;
      J.rightCols<3>() = S * J_ba;
      Eigen::Map<RowMajor3x6>{jacobians[2]} = J;
    }
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

}  // namespace statebench::est
