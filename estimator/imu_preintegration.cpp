#include "estimator/imu_preintegration.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/so3.hpp"

namespace statebench::est {
namespace {

bool AllFinite(const Vec3& v) { return v.allFinite(); }

}  // namespace

ImuSample InterpolateImuSample(const ImuSample& a, const ImuSample& b, TimeNs t_ns) {
  ImuSample out = a;
  out.header.stamp_ns = t_ns;
  const TimeNs span_ns = b.header.stamp_ns - a.header.stamp_ns;
  if (span_ns <= 0) return out;
  const double alpha = static_cast<double>(t_ns - a.header.stamp_ns) / static_cast<double>(span_ns);
  out.gyro = (1.0 - alpha) * a.gyro + alpha * b.gyro;
  out.accel = (1.0 - alpha) * a.accel + alpha * b.accel;
  return out;
}

ImuPreintegration::ImuPreintegration(const ImuNoise& noise, const ImuBias& bias_lin)
    : noise_(noise), bias_lin_(bias_lin) {}

ImuPreintegration ImuPreintegration::FromSamples(std::span<const ImuSample> samples,
                                                 TimeNs t_begin_ns, TimeNs t_end_ns,
                                                 const ImuNoise& noise, const ImuBias& bias_lin) {
  if (samples.empty() || t_end_ns < t_begin_ns || samples.front().header.stamp_ns > t_begin_ns ||
      samples.back().header.stamp_ns < t_end_ns) {
    throw InputError("imu preintegration: samples do not cover the interval [" +
                     std::to_string(t_begin_ns) + ", " + std::to_string(t_end_ns) + "] ns");
  }
  ImuPreintegration pim(noise, bias_lin);
  // Index of the last sample at or before t_begin_ns.
  std::size_t k = 0;
  while (k + 1 < samples.size() && samples[k + 1].header.stamp_ns <= t_begin_ns) ++k;
  const auto stamp = [&](std::size_t n) { return samples[n].header.stamp_ns; };
  pim.Integrate(stamp(k) == t_begin_ns
                    ? samples[k]
                    : InterpolateImuSample(samples[k], samples[k + 1], t_begin_ns));
  for (++k; k < samples.size() && stamp(k) < t_end_ns; ++k) pim.Integrate(samples[k]);
  if (t_end_ns > t_begin_ns) {
    pim.Integrate(stamp(k) == t_end_ns
                      ? samples[k]
                      : InterpolateImuSample(samples[k - 1], samples[k], t_end_ns));
  }
  return pim;
}

void ImuPreintegration::Integrate(TimeNs t_ns, const Vec3& gyro, const Vec3& accel) {
  if (!AllFinite(gyro) || !AllFinite(accel)) {
    throw InputError("imu preintegration: non-finite sample at t_ns " + std::to_string(t_ns));
  }
  const RawSample sample{t_ns, gyro, accel};
  if (!samples_.empty()) {
    if (t_ns <= samples_.back().t_ns) {
      throw InputError("imu preintegration: stamp " + std::to_string(t_ns) +
                       " ns does not increase (previous " + std::to_string(samples_.back().t_ns) +
                       " ns)");
    }
    IntegrateStep(samples_.back(), sample);
  }
  samples_.push_back(sample);
}

void ImuPreintegration::IntegrateStep(const RawSample& s0, const RawSample& s1) {
  const double h = ToSeconds(s1.t_ns - s0.t_ns);
  const Vec3 theta = (0.5 * (s0.gyro + s1.gyro) - bias_lin_.gyro) * h;
  const Vec3 a0 = s0.accel - bias_lin_.accel;
  const Vec3 a1 = s1.accel - bias_lin_.accel;

  const Mat3 dR_step = so3::ExpMatrix(theta);
  const Mat3 jr = so3::RightJacobian(theta);
  const Mat3 R0 = delta_q_.toRotationMatrix();
  const Quat q1 = (delta_q_ * so3::Exp(theta)).normalized();
  const Mat3 R1 = q1.toRotationMatrix();

  // Derivatives of g_k = dR_k a_k and g_k+1 = dR_k+1 a_k+1 w.r.t. the rotation errors.
  const Mat3 G0 = -R0 * so3::Hat(a0);
  const Mat3 G1 = -R1 * so3::Hat(a1);
  const double h2_6 = h * h / 6.0;

  // Bias Jacobians (exact derivatives of the recursion; theta depends on b_g through -h I).
  const Mat3 d_R_d_bg_1 = dR_step.transpose() * d_R_d_bg_ - jr * h;
  const Mat3 dg0_dbg = G0 * d_R_d_bg_;
  const Mat3 dg1_dbg = G1 * d_R_d_bg_1;
  d_p_d_bg_ += d_v_d_bg_ * h + h2_6 * (2.0 * dg0_dbg + dg1_dbg);
  d_p_d_ba_ += d_v_d_ba_ * h - h2_6 * (2.0 * R0 + R1);
  d_v_d_bg_ += 0.5 * h * (dg0_dbg + dg1_dbg);
  d_v_d_ba_ += -0.5 * h * (R0 + R1);
  d_R_d_bg_ = d_R_d_bg_1;

  // Covariance: x_k+1 = A x_k + B_g n_g + B_a n_a, x = (phi, v, p).
  Mat9 A = Mat9::Identity();
  A.block<3, 3>(kPreintRotation, kPreintRotation) = dR_step.transpose();
  A.block<3, 3>(kPreintVelocity, kPreintRotation) = 0.5 * h * (G0 + G1 * dR_step.transpose());
  A.block<3, 3>(kPreintPosition, kPreintRotation) = h2_6 * (2.0 * G0 + G1 * dR_step.transpose());
  A.block<3, 3>(kPreintPosition, kPreintVelocity) = h * Mat3::Identity();
  Eigen::Matrix<double, 9, 3> B_g;
  B_g << jr * h, 0.5 * h * G1 * jr * h, h2_6 * G1 * jr * h;
  Eigen::Matrix<double, 9, 3> B_a;
  B_a << Mat3::Zero(), 0.5 * h * (R0 + R1), h2_6 * (2.0 * R0 + R1);
  const double var_g = noise_.gyro_noise_density * noise_.gyro_noise_density / h;
  const double var_a = noise_.accel_noise_density * noise_.accel_noise_density / h;
  covariance_ = A * covariance_ * A.transpose() + var_g * B_g * B_g.transpose() +
                var_a * B_a * B_a.transpose();
  covariance_.block<3, 3>(kPreintPosition, kPreintPosition).diagonal().array() +=
      noise_.integration_density * noise_.integration_density * h;

  // Deltas (position first: it uses the velocity at k).
  const Vec3 g0 = R0 * a0;
  const Vec3 g1 = R1 * a1;
  delta_p_ += delta_v_ * h + h2_6 * (2.0 * g0 + g1);
  delta_v_ += 0.5 * h * (g0 + g1);
  delta_q_ = q1;
  dt_ += h;
}

ImuPreintegration ImuPreintegration::Reintegrated(const ImuBias& bias_lin) const {
  ImuPreintegration out(noise_, bias_lin);
  for (const RawSample& s : samples_) out.Integrate(s.t_ns, s.gyro, s.accel);
  return out;
}

TimeNs ImuPreintegration::start_ns() const { return samples_.empty() ? 0 : samples_.front().t_ns; }

TimeNs ImuPreintegration::end_ns() const { return samples_.empty() ? 0 : samples_.back().t_ns; }

Quat ImuPreintegration::CorrectedDeltaQ(const ImuBias& bias) const {
  const Vec3 dbg = bias.gyro - bias_lin_.gyro;
  return (delta_q_ * so3::Exp<double>(d_R_d_bg_ * dbg)).normalized();
}

Vec3 ImuPreintegration::CorrectedDeltaV(const ImuBias& bias) const {
  return delta_v_ + d_v_d_bg_ * (bias.gyro - bias_lin_.gyro) +
         d_v_d_ba_ * (bias.accel - bias_lin_.accel);
}

Vec3 ImuPreintegration::CorrectedDeltaP(const ImuBias& bias) const {
  return delta_p_ + d_p_d_bg_ * (bias.gyro - bias_lin_.gyro) +
         d_p_d_ba_ * (bias.accel - bias_lin_.accel);
}

NavState ImuPreintegration::Predict(const NavState& state_i) const {
  const ImuBias bias{state_i.gyro_bias, state_i.accel_bias};
  NavState out = state_i;
  out.t_ns = state_i.t_ns + (end_ns() - start_ns());
  out.q_world_imu = (state_i.q_world_imu * CorrectedDeltaQ(bias)).normalized();
  out.v_world = state_i.v_world + kGravityWorld * dt_ + state_i.q_world_imu * CorrectedDeltaV(bias);
  out.p_world = state_i.p_world + state_i.v_world * dt_ + 0.5 * kGravityWorld * dt_ * dt_ +
                state_i.q_world_imu * CorrectedDeltaP(bias);
  return out;
}

}  // namespace statebench::est
