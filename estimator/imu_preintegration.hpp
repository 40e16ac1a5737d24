// On-manifold IMU preintegration (Forster, Carlone, Dellaert, Scaramuzza, "On-Manifold
// Preintegration for Real-Time Visual-Inertial Odometry", IEEE TRO 2017).
//
// Between the interval start i and its end j the deltas are expressed in the IMU frame at i and
// do not depend on the states (the integration of biased raw samples with a fixed linearisation
// bias b_lin):
//   R_j = R_i dR
//   v_j = v_i + g dt + R_i dv
//   p_j = p_i + v_i dt + 1/2 g dt^2 + R_i dp
// with g = kGravityWorld and dt = t_j - t_i.
//
// Discretisation. The raw signal is taken as piecewise linear between samples (trapezoidal
// rule), which is second-order accurate (global error O(h^2), local O(h^3)):
//   theta   = (1/2 (w_k + w_k+1) - b_g) h,        dR_k+1 = dR_k Exp(theta)
//   g_k     = dR_k (a_k - b_a),                   g_k+1 = dR_k+1 (a_k+1 - b_a)
//   dv_k+1  = dv_k + h/2 (g_k + g_k+1)
//   dp_k+1  = dp_k + h dv_k + h^2/6 (2 g_k + g_k+1)   (exact for g linear on the step)
// The bias Jacobians below are the exact derivatives of this recursion, so the first-order bias
// correction of Forster eq. (44) is exact to first order for this scheme.
//
// Noise. Error state (rotation, velocity, position), 9x9, rotation as a right perturbation
// dR_true = dR Exp(d_phi). Each step carries one gyro and one accel white-noise vector with the
// discrete variance density^2 / h (the mean of continuous white noise over the step, Forster
// eq. 62); summed over many steps this is the variance of the continuous model. A position
// random walk (ImuNoise::integration_density) keeps one-step covariances invertible.
//
// Boundaries at arbitrary stamps: a state or a measurement between two samples is served by a
// sample linearly interpolated at its stamp (InterpolateImuSample), consistent with the
// piecewise-linear model; the interval ending there and the next one starting there share it.
#pragma once

#include <span>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "core/state.hpp"
#include "core/time.hpp"
#include "estimator/imu_bias.hpp"
#include "estimator/imu_noise.hpp"

namespace statebench::est {

// Rows/columns of the preintegrated error state and of the IMU factor residual.
inline constexpr int kPreintRotation = 0;
inline constexpr int kPreintVelocity = 3;
inline constexpr int kPreintPosition = 6;

// Raw IMU sample at t_ns, linearly interpolated between a (earlier) and b (later).
// Requires a.header.stamp_ns <= t_ns <= b.header.stamp_ns and a before b.
ImuSample InterpolateImuSample(const ImuSample& a, const ImuSample& b, TimeNs t_ns);

class ImuPreintegration {
 public:
  ImuPreintegration(const ImuNoise& noise, const ImuBias& bias_lin);

  // Integrates the raw samples (stamps strictly increasing) over exactly [t_begin_ns, t_end_ns]:
  // samples at the two ends are interpolated when no sample falls on them. The samples must
  // cover the interval (first stamp <= t_begin_ns, last stamp >= t_end_ns); InputError otherwise.
  static ImuPreintegration FromSamples(std::span<const ImuSample> samples, TimeNs t_begin_ns,
                                       TimeNs t_end_ns, const ImuNoise& noise,
                                       const ImuBias& bias_lin);

  // Adds the raw sample (rad/s, m/s^2 specific force, IMU frame) measured at t_ns. The first
  // sample opens the interval; each later one integrates the step from the previous sample.
  // InputError if t_ns does not increase or a value is not finite; the state is then unchanged.
  void Integrate(TimeNs t_ns, const Vec3& gyro, const Vec3& accel);
  void Integrate(const ImuSample& sample) {
    Integrate(sample.header.stamp_ns, sample.gyro, sample.accel);
  }

  // The same raw samples integrated again around a new linearisation bias (exact, not first
  // order). Use when the estimated bias moved far from bias_lin().
  ImuPreintegration Reintegrated(const ImuBias& bias_lin) const;

  bool empty() const { return samples_.size() < 2; }
  TimeNs start_ns() const;
  TimeNs end_ns() const;
  double dt() const { return dt_; }  // s
  int num_steps() const { return samples_.empty() ? 0 : static_cast<int>(samples_.size()) - 1; }

  const ImuNoise& noise() const { return noise_; }
  const ImuBias& bias_lin() const { return bias_lin_; }
  const Quat& delta_q() const { return delta_q_; }
  Mat3 delta_R() const { return delta_q_.toRotationMatrix(); }
  const Vec3& delta_v() const { return delta_v_; }
  const Vec3& delta_p() const { return delta_p_; }
  // 9x9 covariance of (rotation, velocity, position) deltas, see kPreint*.
  const Mat9& covariance() const { return covariance_; }

  // First-order bias Jacobians at bias_lin (rotation in the right-perturbation sense:
  // dR(b_lin + db) ~= dR Exp(d_R_d_bg db_g)).
  const Mat3& d_R_d_bg() const { return d_R_d_bg_; }
  const Mat3& d_v_d_bg() const { return d_v_d_bg_; }
  const Mat3& d_v_d_ba() const { return d_v_d_ba_; }
  const Mat3& d_p_d_bg() const { return d_p_d_bg_; }
  const Mat3& d_p_d_ba() const { return d_p_d_ba_; }

  // Deltas corrected to first order for bias b (Forster eq. 44).
  Quat CorrectedDeltaQ(const ImuBias& bias) const;
  Vec3 CorrectedDeltaV(const ImuBias& bias) const;
  Vec3 CorrectedDeltaP(const ImuBias& bias) const;

  // State at end_ns() predicted from state_i (at start_ns()) with its biases, which are kept.
  NavState Predict(const NavState& state_i) const;

  struct RawSample {
    TimeNs t_ns = 0;
    Vec3 gyro = Vec3::Zero();
    Vec3 accel = Vec3::Zero();
  };
  const std::vector<RawSample>& samples() const { return samples_; }

 private:
  void IntegrateStep(const RawSample& s0, const RawSample& s1);

  ImuNoise noise_;
  ImuBias bias_lin_;
  std::vector<RawSample> samples_;
  double dt_ = 0.0;
  Quat delta_q_ = Quat::Identity();
  Vec3 delta_v_ = Vec3::Zero();
  Vec3 delta_p_ = Vec3::Zero();
  Mat9 covariance_ = Mat9::Zero();
  Mat3 d_R_d_bg_ = Mat3::Zero();
  Mat3 d_v_d_bg_ = Mat3::Zero();
  Mat3 d_v_d_ba_ = Mat3::Zero();
  Mat3 d_p_d_bg_ = Mat3::Zero();
  Mat3 d_p_d_ba_ = Mat3::Zero();
};

}  // namespace statebench::est
