#include "estimator/state_initializer.hpp"

// The moving start refined over every fix of its chord (state_initializer.hpp, MovingAnchor).
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/so3.hpp"

namespace statebench::est {
namespace {

using Mat9x9 = Eigen::Matrix<double, 9, 9>;
using Vec9x1 = Eigen::Matrix<double, 9, 1>;
constexpr int kMovingFitIterations = 4;
constexpr std::size_t kMovingFitMinFixes = 4;

}  // namespace

// MovingAnchor's three fixes give the attitude and velocity at t_a exactly if the fixes were;
// with fixes of metres (CEP 2 m) over a ten-second chord of a vehicle that accelerates, the
// velocity is off by a metre per second. Every fix k of the chord measures the antenna as
//   p_enu_k = p_a + v_a tau_k + g tau_k^2 / 2 + R_a u_k,   u_k = dp_k + dR_k l_k,
// with dp, dR preintegrated from t_a (IMU frame at t_a, gyro bias zero). Gauss-Newton on
// (p_a, v_a, R_a = R Exp(dtheta)) over all of them, weighted by their covariances, with the
// three-fix attitude as a prior (tilt sigma moving_roll_pitch_sigma_rad, yaw the reference's
// sigma, about the world axes): the velocity then rests on every fix, not two. The fit is kept
// only if it converges to finite values. Its covariance is the inverse of the normal matrix at
// the solution, scaled up by the fixes' own scatter about the fit when it is larger than their
// covariances say (chi-square over the degrees of freedom, never below 1): what the model
// leaves out (the IMU's biases over the chord, a receiver's slow error) shows there.
void StateInitializer::FitMovingAnchor(const Fix& a, const YawReference& yaw,
                                       Anchor* anchor) const {
  const TimeNs t_a = a.fix.header.stamp_ns;
  const TimeNs t_b = fixes_.back().fix.header.stamp_ns;
  std::vector<const Fix*> chord;
  for (const Fix& f : fixes_) {
    const TimeNs t = f.fix.header.stamp_ns;
    if (t >= t_a && t <= t_b) chord.push_back(&f);
  }
  if (chord.size() < kMovingFitMinFixes) return;
  std::vector<Vec3> u(chord.size());
  std::vector<double> tau(chord.size());
  std::vector<Mat3> W(chord.size());
  for (std::size_t k = 0; k < chord.size(); ++k) {
    const TimeNs t = chord[k]->fix.header.stamp_ns;
    tau[k] = ToSeconds(t - t_a);
    if (t == t_a) {
      u[k] = chord[k]->p_imu_antenna;
    } else {
      const ImuPreintegration pim = Preintegrate(t_a, t, Vec3::Zero());
      u[k] = pim.delta_p() + pim.delta_q() * chord[k]->p_imu_antenna;
    }
    const Eigen::LDLT<Mat3> ldlt(chord[k]->fix.covariance);
    if (ldlt.info() != Eigen::Success) return;
    W[k] = ldlt.solve(Mat3::Identity());
  }

  NavState x = anchor->state;
  Mat9x9 H = Mat9x9::Zero();
  double chi2 = 0.0;
  const Mat3 R_prior = x.q_world_imu.toRotationMatrix();
  const double sigma_tilt = options_.moving_roll_pitch_sigma_rad;
  const Vec3 prior_information(1.0 / (sigma_tilt * sigma_tilt), 1.0 / (sigma_tilt * sigma_tilt),
                               1.0 / (yaw.sigma_rad * yaw.sigma_rad));
  for (int iteration = 0; iteration < kMovingFitIterations; ++iteration) {
    const Mat3 R = x.q_world_imu.toRotationMatrix();
    H.setZero();
    chi2 = 0.0;
    Vec9x1 g = Vec9x1::Zero();
    for (std::size_t k = 0; k < chord.size(); ++k) {
      const Vec3 predicted = x.p_world + x.v_world * tau[k] +
                             0.5 * kGravityWorld * tau[k] * tau[k] + R * u[k];
      const Vec3 r = chord[k]->fix.p_enu - predicted;
      Eigen::Matrix<double, 3, 9> J;
      J << Mat3::Identity(), tau[k] * Mat3::Identity(), -R * so3::Hat(u[k]);
      H.noalias() += J.transpose() * W[k] * J;
      g.noalias() += J.transpose() * W[k] * r;
      chi2 += r.dot(W[k] * r);
    }
    // The prior on the world-frame attitude error phi = log(R R_prior^T), phi ~ R dtheta.
    const Vec3 phi = so3::Log<double>(Quat(R * R_prior.transpose()));
    const Mat3 prior = R.transpose() * prior_information.asDiagonal() * R;  // on dtheta
    H.bottomRightCorner<3, 3>() += prior;
    g.tail<3>() -= R.transpose() * (prior_information.asDiagonal() * phi);
    const Eigen::LDLT<Mat9x9> ldlt(H);
    if (ldlt.info() != Eigen::Success) return;
    const Vec9x1 dx = ldlt.solve(g);
    if (!dx.allFinite()) return;
    x.p_world += dx.head<3>();
    x.v_world += dx.segment<3>(3);
    x.q_world_imu = (x.q_world_imu * so3::Exp<double>(dx.tail<3>())).normalized();
    if (dx.norm() < 1e-9) break;
  }
  if (!x.p_world.allFinite() || !x.v_world.allFinite() || !x.q_world_imu.coeffs().allFinite()) {
    return;
  }
  // The normal matrix and chi-square of the last linearisation (at most one step from x).
  const Eigen::LDLT<Mat9x9> ldlt(H);
  const Mat9x9 covariance = ldlt.solve(Mat9x9::Identity());
  const double dof = 3.0 * static_cast<double>(chord.size()) - 9.0;
  const double scale = dof > 0.0 ? std::max(1.0, chi2 / dof) : 1.0;
  anchor->state = x;
  if (ldlt.info() == Eigen::Success && covariance.allFinite()) {
    anchor->fit_covariance = scale * 0.5 * (covariance + covariance.transpose());
  }
}

}  // namespace statebench::est
