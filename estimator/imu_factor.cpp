#include "estimator/imu_factor.hpp"

#include "core/error.hpp"
#include "core/so3.hpp"
#include "estimator/so3_manifold.hpp"
#include "estimator/sqrt_information.hpp"
#include "estimator/state_parameters.hpp"

namespace statebench::est {
namespace {

using RowMajor9x3 = Eigen::Matrix<double, 9, 3, Eigen::RowMajor>;
using RowMajor9x4 = Eigen::Matrix<double, 9, 4, Eigen::RowMajor>;
using RowMajor9x6 = Eigen::Matrix<double, 9, 6, Eigen::RowMajor>;

Mat9 CheckedSqrtInformation(const ImuPreintegration& pim) {
  if (pim.empty()) throw InputError("imu factor: empty preintegration");
  return SqrtInformation<9>(pim.covariance(), "imu factor");
}

}  // namespace

ImuFactor::ImuFactor(ImuPreintegration preintegration)
    : preintegration_(std::move(preintegration)),
      sqrt_information_(CheckedSqrtInformation(preintegration_)) {}

Vec9 ImuFactor::Residual(const NavState& si, const NavState& sj) const {
  const StateParameters pi = StateParameters::FromNavState(si);
  const StateParameters pj = StateParameters::FromNavState(sj);
  const double* params[] = {pi.q_world_imu.data(), pi.p_world.data(),     pi.v_world.data(),
                            pi.bias.data(),        pj.q_world_imu.data(), pj.p_world.data(),
                            pj.v_world.data()};
  Vec9 whitened;
  Evaluate(params, whitened.data(), nullptr);
  return sqrt_information_.triangularView<Eigen::Lower>().solve(whitened);
}

bool ImuFactor::Evaluate(double const* const* parameters, double* residuals,
                         double** jacobians) const {
  const Quat q_i = Eigen::Map<const Quat>(parameters[0]).normalized();
  const Eigen::Map<const Vec3> p_i(parameters[1]);
  const Eigen::Map<const Vec3> v_i(parameters[2]);
  const Eigen::Map<const Vec6> bias_i(parameters[3]);
  const Quat q_j = Eigen::Map<const Quat>(parameters[4]).normalized();
  const Eigen::Map<const Vec3> p_j(parameters[5]);
  const Eigen::Map<const Vec3> v_j(parameters[6]);

  const ImuPreintegration& pim = preintegration_;
  const double dt = pim.dt();
  const Vec3 dbg = bias_i.head<3>() - pim.bias_lin().gyro;
  const Vec3 dba = bias_i.tail<3>() - pim.bias_lin().accel;
  const Vec3 phi_bg = pim.d_R_d_bg() * dbg;
  const Quat dq_c = pim.delta_q() * so3::Exp<double>(phi_bg);
  const Vec3 dv_c = pim.delta_v() + pim.d_v_d_bg() * dbg + pim.d_v_d_ba() * dba;
  const Vec3 dp_c = pim.delta_p() + pim.d_p_d_bg() * dbg + pim.d_p_d_ba() * dba;

  const Mat3 Ri_T = q_i.conjugate().toRotationMatrix();
  const Vec3 v_rel = Ri_T * (v_j - v_i - kGravityWorld * dt);
  const Vec3 p_rel = Ri_T * (p_j - p_i - v_i * dt - 0.5 * kGravityWorld * dt * dt);
  const Quat q_err = dq_c.conjugate() * q_i.conjugate() * q_j;

  Vec9 r;
  r.segment<3>(kPreintRotation) = so3::Log<double>(q_err);
  r.segment<3>(kPreintVelocity) = v_rel - dv_c;
  r.segment<3>(kPreintPosition) = p_rel - dp_c;
  Eigen::Map<Vec9>{residuals} = sqrt_information_ * r;
  if (jacobians == nullptr) return true;

  // Each Jacobian is S J with J made of 3x3 blocks, many zero: S J = sum over J's nonzero row
  // blocks b of S's column block b times J_b (lazy fixed-size products, no GEMM).
  const Mat9& S = sqrt_information_;
  const auto S_R = S.middleCols<3>(kPreintRotation);
  const auto S_v = S.middleCols<3>(kPreintVelocity);
  const auto S_p = S.middleCols<3>(kPreintPosition);
  const Vec3 r_R = r.segment<3>(kPreintRotation);
  const Mat3 Jr_inv = so3::RightJacobianInverse(r_R);
  if (jacobians[0] != nullptr) {  // q_i
    const Mat3 J_R = -Jr_inv * (q_j.conjugate() * q_i).toRotationMatrix();
    const RowMajor9x3 SJ = S_R.lazyProduct(J_R) + S_v.lazyProduct(so3::Hat<double>(v_rel)) +
                           S_p.lazyProduct(so3::Hat<double>(p_rel));
    Eigen::Map<RowMajor9x4>{jacobians[0]} = SJ.lazyProduct(QuaternionMinusJacobian(parameters[0]));
  }
  if (jacobians[1] != nullptr) {  // p_i
    Eigen::Map<RowMajor9x3>{jacobians[1]} = -S_p.lazyProduct(Ri_T);
  }
  if (jacobians[2] != nullptr) {  // v_i
    Eigen::Map<RowMajor9x3>{jacobians[2]} = -(S_v + dt * S_p).lazyProduct(Ri_T);
  }
  if (jacobians[3] != nullptr) {  // bias_i
    const Mat3 J_R_bg =
        -Jr_inv * so3::ExpMatrix<double>(-r_R) * so3::RightJacobian(phi_bg) * pim.d_R_d_bg();
    Eigen::Map<RowMajor9x6> J{jacobians[3]};
    J.leftCols<3>() = S_R.lazyProduct(J_R_bg) - S_v.lazyProduct(pim.d_v_d_bg()) -
                      S_p.lazyProduct(pim.d_p_d_bg());
    J.rightCols<3>() = -S_v.lazyProduct(pim.d_v_d_ba()) - S_p.lazyProduct(pim.d_p_d_ba());
  }
  if (jacobians[4] != nullptr) {  // q_j
    const RowMajor9x3 SJ = S_R.lazyProduct(Jr_inv);
    Eigen::Map<RowMajor9x4>{jacobians[4]} = SJ.lazyProduct(QuaternionMinusJacobian(parameters[4]));
  }
  if (jacobians[5] != nullptr) {  // p_j
    Eigen::Map<RowMajor9x3>{jacobians[5]} = S_p.lazyProduct(Ri_T);
  }
  if (jacobians[6] != nullptr) {  // v_j
    Eigen::Map<RowMajor9x3>{jacobians[6]} = S_v.lazyProduct(Ri_T);
  }
  return true;
}

}  // namespace statebench::est
