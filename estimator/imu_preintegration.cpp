#include "estimator/imu_preintegration.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>

#include "core/error.hpp"
#include "core/so3.hpp"
#include "estimator/mat3_blocks.hpp"

namespace statebench::est {
namespace {

using RawSample = ImuPreintegration::RawSample;

// Samples per interpolation stencil (cubic).
constexpr std::size_t kStencil = 4;

bool AllFinite(const Vec3& v) { return v.allFinite(); }

RawSample ToRaw(const ImuSample& s) { return {s.header.stamp_ns, s.gyro, s.accel}; }

// Lagrange polynomial through raw[j-n+1 .. j], n = min(j + 1, kStencil), in the time x (s)
// relative to raw[j].
class GapInterpolant {
 public:
  GapInterpolant(const std::vector<RawSample>& raw, std::size_t j)
      : n_(std::min(j + 1, kStencil)), first_(&raw[j + 1 - n_]) {
    for (std::size_t i = 0; i < n_; ++i) x_[i] = -ToSeconds(raw[j].t_ns - first_[i].t_ns);
    for (std::size_t i = 0; i < n_; ++i) {
      double d = 1.0;
      for (std::size_t m = 0; m < n_; ++m) {
        if (m != i) d *= x_[i] - x_[m];
      }
      inv_denominator_[i] = 1.0 / d;
    }
  }

  Vec3 Gyro(double x) const { return Evaluate(x, &RawSample::gyro); }
  Vec3 Accel(double x) const { return Evaluate(x, &RawSample::accel); }

 private:
  Vec3 Evaluate(double x, Vec3 RawSample::*signal) const {
    Vec3 out = Vec3::Zero();
    for (std::size_t i = 0; i < n_; ++i) {
      double w = inv_denominator_[i];
      for (std::size_t m = 0; m < n_; ++m) {
        if (m != i) w *= x - x_[m];
      }
      out += w * (first_[i].*signal);
    }
    return out;
  }

  std::size_t n_;
  const RawSample* first_;
  std::array<double, kStencil> x_{};
  std::array<double, kStencil> inv_denominator_{};
};

// Fourth-order Magnus step over a half of length H from the rates at its two Gauss points
// (see the header) and its derivative with respect to a constant rate offset added to both
// (the noise; minus the derivative with respect to the gyro bias).
struct MagnusStep {
  Vec3 omega;
  Mat3 d_omega_d_rate;
};

MagnusStep Magnus(const Vec3& w1, const Vec3& w2, double H) {
  const double c = std::sqrt(3.0) / 12.0 * H * H;
  return {0.5 * H * (w1 + w2) + c * w1.cross(w2),
          H * Mat3::Identity() - c * (so3::Hat(w2) - so3::Hat(w1))};
}

// The samples FromSamples integrates over [t_begin_ns, t_end_ns] (covered): k0 the last at or
// before t_begin_ns, k1 the first at or after t_end_ns, first the stencil's start before k0 (the
// first gap (k0, k0 + 1] uses the stencil k0 - 2 .. k0 + 1).
struct SampleRange {
  std::size_t first, k0, k1;
};

SampleRange SampleRangeOf(std::span<const ImuSample> samples, TimeNs t_begin_ns,
                          TimeNs t_end_ns) {
  // Number of samples at or before t_ns.
  const auto count_until = [&](TimeNs t_ns) {
    const auto it =
        std::upper_bound(samples.begin(), samples.end(), t_ns,
                         [](TimeNs t, const ImuSample& s) { return t < s.header.stamp_ns; });
    return static_cast<std::size_t>(it - samples.begin());
  };
  const std::size_t k0 = count_until(t_begin_ns) - 1;
  std::size_t k1 = count_until(t_end_ns) - 1;
  if (samples[k1].header.stamp_ns < t_end_ns) ++k1;
  return {k0 >= kStencil - 2 ? k0 - (kStencil - 2) : 0, k0, k1};
}

bool SameBits(const Vec3& a, const Vec3& b) {
  return std::memcmp(a.data(), b.data(), sizeof(Vec3)) == 0;
}

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
  const auto [first, k0, k1] = SampleRangeOf(samples, t_begin_ns, t_end_ns);

  ImuPreintegration pim(noise, bias_lin);
  pim.raw_.reserve(k1 - first + 1);
  for (std::size_t k = first; k <= k1; ++k) {
    if (!AllFinite(samples[k].gyro) || !AllFinite(samples[k].accel)) {
      throw InputError("imu preintegration: non-finite sample at t_ns " +
                       std::to_string(samples[k].header.stamp_ns));
    }
    if (k > first && samples[k].header.stamp_ns <= samples[k - 1].header.stamp_ns) {
      throw InputError("imu preintegration: stamp " + std::to_string(samples[k].header.stamp_ns) +
                       " ns does not increase");
    }
    pim.raw_.push_back(ToRaw(samples[k]));
  }
  // Gap of raw_ that t_begin_ns opens (or the sample it sits on, when it is the last one).
  std::size_t j = k0 - first + 1;
  if (j == pim.raw_.size()) {  // t_begin_ns == t_end_ns == last stamp
    pim.samples_.push_back(pim.raw_.back());
    return pim;
  }
  if (pim.raw_[j - 1].t_ns == t_begin_ns) {
    pim.samples_.push_back(pim.raw_[j - 1]);
  } else {
    const GapInterpolant signal(pim.raw_, j);
    const double x = -ToSeconds(pim.raw_[j].t_ns - t_begin_ns);
    pim.samples_.push_back({t_begin_ns, signal.Gyro(x), signal.Accel(x)});
  }
  if (t_end_ns == t_begin_ns) return pim;
  for (; pim.raw_[j].t_ns < t_end_ns; ++j) pim.Advance(j, pim.raw_[j].t_ns);
  pim.Advance(j, t_end_ns);
  return pim;
}

void ImuPreintegration::Integrate(TimeNs t_ns, const Vec3& gyro, const Vec3& accel) {
  if (!AllFinite(gyro) || !AllFinite(accel)) {
    throw InputError("imu preintegration: non-finite sample at t_ns " + std::to_string(t_ns));
  }
  const RawSample sample{t_ns, gyro, accel};
  if (samples_.empty()) {
    raw_.assign(1, sample);
    samples_.push_back(sample);
    return;
  }
  if (t_ns <= end_ns()) {
    throw InputError("imu preintegration: stamp " + std::to_string(t_ns) +
                     " ns does not increase (previous " + std::to_string(end_ns()) + " ns)");
  }
  const RawSample& ahead = raw_.back();
  if (ahead.t_ns > end_ns()) {  // the interval ends between samples, before `ahead`
    if (t_ns < ahead.t_ns || (t_ns == ahead.t_ns && (gyro != ahead.gyro || accel != ahead.accel))) {
      throw InputError("imu preintegration: sample at " + std::to_string(t_ns) +
                       " ns conflicts with the sample at " + std::to_string(ahead.t_ns) +
                       " ns already used to interpolate the interval end");
    }
    Advance(raw_.size() - 1, ahead.t_ns);
    if (t_ns == ahead.t_ns) return;
  }
  raw_.push_back(sample);
  Advance(raw_.size() - 1, t_ns);
}

void ImuPreintegration::Advance(std::size_t j, TimeNs t_ns) {
  const GapInterpolant signal(raw_, j);
  const TimeNs t0_ns = samples_.back().t_ns;
  const double h = ToSeconds(t_ns - t0_ns);
  const double x0 = -ToSeconds(raw_[j].t_ns - t0_ns);  // s, relative to raw_[j]
  const double half = 0.5 * h;
  const double gauss_lo = half * (0.5 - std::sqrt(3.0) / 6.0);
  const double gauss_hi = half * (0.5 + std::sqrt(3.0) / 6.0);

  // Bias-corrected rates: at the Gauss points of both halves (gyro), at the start, middle and
  // end (accelerometer).
  const RawSample node =
      raw_[j].t_ns == t_ns ? raw_[j] : RawSample{t_ns, signal.Gyro(x0 + h), signal.Accel(x0 + h)};
  const Vec3 w[4] = {signal.Gyro(x0 + gauss_lo) - bias_lin_.gyro,
                     signal.Gyro(x0 + gauss_hi) - bias_lin_.gyro,
                     signal.Gyro(x0 + half + gauss_lo) - bias_lin_.gyro,
                     signal.Gyro(x0 + half + gauss_hi) - bias_lin_.gyro};
  const Vec3 a[3] = {samples_.back().accel - bias_lin_.accel,
                     signal.Accel(x0 + half) - bias_lin_.accel, node.accel - bias_lin_.accel};

  // Rotation: two Magnus half steps.
  const MagnusStep step_a = Magnus(w[0], w[1], half);
  const MagnusStep step_b = Magnus(w[2], w[3], half);
  const Quat q_a = so3::Exp(step_a.omega);
  const Quat q_b = so3::Exp(step_b.omega);
  const Mat3 E_a = q_a.toRotationMatrix();
  const Mat3 E_b = q_b.toRotationMatrix();
  const Mat3 dR_step_T = (E_a * E_b).transpose();
  const Quat q_m = delta_q_ * q_a;
  const Quat q1 = (q_m * q_b).normalized();
  const Mat3 R0 = delta_q_.toRotationMatrix();
  const Mat3 Rm = q_m.toRotationMatrix();
  const Mat3 R1 = q1.toRotationMatrix();

  // Derivatives of g = dR a w.r.t. the rotation error at that point.
  const Mat3 G0 = -R0 * so3::Hat(a[0]);
  const Mat3 Gm = -Rm * so3::Hat(a[1]);
  const Mat3 G1 = -R1 * so3::Hat(a[2]);
  const double h_6 = h / 6.0;
  const double h2_6 = h * h_6;

  // Linearised step x_1 = A x_0 + B_g n_g + B_a n_a, x = (phi, v, p), with n constant rate
  // offsets over the step (a gyro/accel bias change db enters as n = -db).
  const Mat3 phi_m_n = so3::RightJacobian(step_a.omega) * step_a.d_omega_d_rate;
  const Mat3 phi_1_n =
      E_b.transpose() * phi_m_n + so3::RightJacobian(step_b.omega) * step_b.d_omega_d_rate;
  const Mat3 A_v_phi = h_6 * (G0 + 4.0 * Gm * E_a.transpose() + G1 * dR_step_T);
  const Mat3 A_p_phi = h2_6 * (G0 + 2.0 * Gm * E_a.transpose());
  const Mat3 B_g_v = h_6 * (4.0 * Gm * phi_m_n + G1 * phi_1_n);
  const Mat3 B_g_p = h2_6 * 2.0 * Gm * phi_m_n;
  const Mat3 B_a_v = h_6 * (R0 + 4.0 * Rm + R1);
  const Mat3 B_a_p = h2_6 * (R0 + 2.0 * Rm);

  // Bias Jacobians: J_1 = A J_0 - B (exact derivatives of the recursion).
  d_p_d_bg_ += d_v_d_bg_ * h + A_p_phi * d_R_d_bg_ - B_g_p;
  d_p_d_ba_ += d_v_d_ba_ * h - B_a_p;
  d_v_d_bg_ += A_v_phi * d_R_d_bg_ - B_g_v;
  d_v_d_ba_ -= B_a_v;
  d_R_d_bg_ = dR_step_T * d_R_d_bg_ - phi_1_n;

  // Covariance (3x3 blocks: rotation 0, velocity 1, position 2; kPreint*).
  Mat3Blocks<3, 3> A;
  A.SetGeneral(0, 0, dR_step_T);
  A.SetGeneral(1, 0, A_v_phi);
  A.SetIdentity(1, 1);
  A.SetGeneral(2, 0, A_p_phi);
  A.SetScaledIdentity(2, 1, h);
  A.SetIdentity(2, 2);
  Mat3Blocks<3, 1> B_g;
  B_g.SetGeneral(0, 0, phi_1_n);
  B_g.SetGeneral(1, 0, B_g_v);
  B_g.SetGeneral(2, 0, B_g_p);
  Mat3Blocks<3, 1> B_a;
  B_a.SetGeneral(1, 0, B_a_v);
  B_a.SetGeneral(2, 0, B_a_p);
  const double var_g = noise_.gyro_noise_density * noise_.gyro_noise_density / h;
  const double var_a = noise_.accel_noise_density * noise_.accel_noise_density / h;
  covariance_ = A.Congruence(covariance_) + B_g.ScaledGram(var_g) + B_a.ScaledGram(var_a);
  covariance_.block<3, 3>(kPreintPosition, kPreintPosition).diagonal().array() +=
      noise_.integration_density * noise_.integration_density * h;

  // Deltas (position first: it uses the velocity at t0).
  const Vec3 g0 = R0 * a[0];
  const Vec3 gm = Rm * a[1];
  const Vec3 g1 = R1 * a[2];
  delta_p_ += delta_v_ * h + h2_6 * (g0 + 2.0 * gm);
  delta_v_ += h_6 * (g0 + 4.0 * gm + g1);
  delta_q_ = q1;
  dt_ += h;
  samples_.push_back(node);
}

bool ImuPreintegration::StartsAs(TimeNs t_begin_ns, const ImuNoise& noise,
                                 const ImuBias& bias_lin) const {
  return !samples_.empty() && start_ns() == t_begin_ns && noise_ == noise &&
         SameBits(bias_lin_.gyro, bias_lin.gyro) && SameBits(bias_lin_.accel, bias_lin.accel);
}

bool ImuPreintegration::IntegratesSamplesOf(std::span<const ImuSample> samples) const {
  if (samples_.empty() || samples.empty() || samples.front().header.stamp_ns > start_ns() ||
      samples.back().header.stamp_ns < end_ns()) {
    return false;
  }
  const auto [first, k0, k1] = SampleRangeOf(samples, start_ns(), end_ns());
  if (raw_.size() != k1 - first + 1) return false;
  for (std::size_t i = 0; i < raw_.size(); ++i) {
    const ImuSample& s = samples[first + i];
    if (raw_[i].t_ns != s.header.stamp_ns || !SameBits(raw_[i].gyro, s.gyro) ||
        !SameBits(raw_[i].accel, s.accel)) {
      return false;
    }
  }
  return true;
}

ImuPreintegration ImuPreintegration::Reintegrated(const ImuBias& bias_lin) const {
  ImuPreintegration out(noise_, bias_lin);
  out.raw_ = raw_;
  if (samples_.empty()) return out;
  out.samples_.reserve(samples_.size());
  out.samples_.push_back(samples_.front());
  std::size_t j = 0;
  for (std::size_t n = 1; n < samples_.size(); ++n) {
    while (raw_[j].t_ns < samples_[n].t_ns) ++j;
    out.Advance(j, samples_[n].t_ns);
  }
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
