#include "estimator/odometry_alignment.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "core/state.hpp"
#include "estimator/body_velocity_front_end.hpp"
#include "estimator/imu_preintegration.hpp"

namespace statebench::est {
namespace {

// The raw gyro at t_ns, interpolated; nullopt outside the samples.
std::optional<Vec3> GyroAt(std::span<const ImuSample> imu, TimeNs t_ns) {
  if (imu.empty() || t_ns < imu.front().header.stamp_ns || t_ns > imu.back().header.stamp_ns) {
    return std::nullopt;
  }
  const auto b = std::lower_bound(imu.begin(), imu.end(), t_ns, [](const ImuSample& s, TimeNs t) {
    return s.header.stamp_ns < t;
  });
  if (b->header.stamp_ns == t_ns) return b->gyro;
  return InterpolateImuSample(*std::prev(b), *b, t_ns).gyro;
}

}  // namespace

Vec3 ImuVelocityOf(const OdometryVelocity& v, const Vec3& gyro, Mat3* covariance) {
  Vec3 v_frame = v.v_frame;
  Vec3 variance = v.variance;
  for (int i = 0; i < 3; ++i) {
    if (!(variance[i] < BodyVelocityFrontEnd::kUnmeasuredVariance)) {
      v_frame[i] = 0.0;
      variance[i] = kUnmeasuredSigmaMps * kUnmeasuredSigmaMps;
    }
    const double floor = BodyVelocityFrontEnd::kMinSigmaMps;
    variance[i] = std::max(variance[i], floor * floor);
  }
  const Mat3 Q = v.q_imu_frame.toRotationMatrix();
  if (covariance != nullptr) *covariance = Q * variance.asDiagonal() * Q.transpose();
  return Q * v_frame - gyro.cross(v.p_imu_point);
}

std::optional<OdometryAlignment> AlignWithOdometry(std::span<const ImuSample> imu,
                                                   std::span<const OdometryVelocity> odometry,
                                                   const ImuNoise& noise, const Vec3& gyro_bias) {
  if (odometry.size() < 3) return std::nullopt;
  const TimeNs t_a = odometry.front().t_ns;
  // Normal equations of u_a + tau_k G = dR_k u_k - dv_k, each row block weighted by the inverse
  // covariance of its right-hand side (the odometry noise rotated by dR_k).
  Mat6 normal = Mat6::Zero();
  Vec6 rhs = Vec6::Zero();
  for (const OdometryVelocity& v : odometry) {
    const std::optional<Vec3> gyro = GyroAt(imu, v.t_ns);
    if (!gyro || v.t_ns < t_a) return std::nullopt;
    Mat3 covariance;
    const Vec3 u_k = ImuVelocityOf(v, *gyro - gyro_bias, &covariance);
    Mat3 dR = Mat3::Identity();
    Vec3 dv = Vec3::Zero();
    if (v.t_ns > t_a) {
      const ImuPreintegration pim =
          ImuPreintegration::FromSamples(imu, t_a, v.t_ns, noise, ImuBias{gyro_bias, Vec3::Zero()});
      dR = pim.delta_R();
      dv = pim.delta_v();
    }
    const double tau = ToSeconds(v.t_ns - t_a);
    const Mat3 W = (dR * covariance * dR.transpose()).inverse();
    Eigen::Matrix<double, 3, 6> A;
    A << Mat3::Identity(), tau * Mat3::Identity();
    normal += A.transpose() * W * A;
    rhs += A.transpose() * W * (dR * u_k - dv);
  }
  const Eigen::LDLT<Mat6> ldlt(normal);
  if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-12)) return std::nullopt;
  const Vec6 x = ldlt.solve(rhs);
  const Vec3 G = x.tail<3>();
  if (!x.allFinite() || !(G.norm() > 0.0)) return std::nullopt;
  OdometryAlignment out;
  out.t_a_ns = t_a;
  out.t_b_ns = odometry.back().t_ns;
  out.u_imu = x.head<3>();
  out.gravity_mps2 = G.norm();
  out.up_imu = -G / G.norm();
  out.covariance = ldlt.solve(Mat6::Identity());
  return out;
}

}  // namespace statebench::est
