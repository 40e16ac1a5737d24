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
// Discretisation (fourth order). The raw signal (gyro and accelerometer, each axis) is taken
// as piecewise cubic: on the gap [t_k-1, t_k] between two raw samples it is the Lagrange
// polynomial through the samples t_k-3 .. t_k. The stencil ends at t_k, so a step never needs a
// sample after its own end (states are created when a sample arrives); the gap lies inside the
// stencil's hull, so this is interpolation with error O(h^4). Earlier samples in the buffer
// given to FromSamples, or the previous samples seen by Integrate, serve as stencil context; when
// fewer exist (at the very start of a stream) the stencil shrinks to 3 or 2 samples (quadratic,
// linear: local error O(h^4), O(h^3) on those first steps only). The piecewise signal is
// continuous and defined by the raw samples alone: an interval ending at an arbitrary stamp and
// the next one starting there integrate the same signal.
//
// A step [t0, t1] (a whole gap, or the part of one from or to an interval end; h = t1 - t0, tm
// its middle) with bias-corrected rates w(t) = w_raw(t) - b_g, a(t) = a_raw(t) - b_a:
//   rotation: fourth-order Magnus step on each half [t0, tm], [tm, t1], with the rates w1, w2
//     at the two Gauss points t + H (1/2 -+ sqrt(3)/6) of a half [t, t + H],
//       Omega = H/2 (w1 + w2) + sqrt(3)/12 H^2 (w1 x w2),   dR_m = dR_0 Exp(Omega_a),
//       dR_1 = dR_m Exp(Omega_b)      (local error O(h^5))
//   g = dR a at t0, tm, t1 (g0, gm, g1), Simpson's rule (local error O(h^5)):
//       dv_1 = dv_0 + h/6 (g0 + 4 gm + g1)
//       dp_1 = dp_0 + h dv_0 + h^2/6 (g0 + 2 gm)   (Simpson on the integrand (t1 - t) g(t))
// The global error against the continuous truth is O(h^4). At 100 Hz on a car-like motion (yaw
// rate up to 1.1 rad/s, lateral acceleration up to 6 m/s^2) it is at most 5e-10 rad, 2.4e-9 m/s,
// 1.4e-10 m over 0.1 s and 2.2e-9 rad, 3.2e-8 m/s, 1.4e-8 m over 1 s, where the former
// trapezoidal scheme (second order) erred 1.1e-6 rad, 4.5e-6 m/s, 2.6e-7 m and 1.4e-5 rad,
// 1e-4 m/s, 3.8e-5 m (tests/estimator/imu_preintegration_accuracy_test.cpp). Without earlier
// samples the linear first step dominates: up to 1e-7 rad, 6e-7 m/s, 5.3e-7 m over 1 s.
// The bias Jacobians below are the exact derivatives of this recursion (the bias shifts the
// interpolated rates by a constant), so the first-order bias correction of Forster eq. (44)
// differs from a re-integration with the new bias by O(|db|^2) only.
//
// Noise. Error state (rotation, velocity, position), 9x9, rotation as a right perturbation
// dR_true = dR Exp(d_phi). Each step carries one gyro and one accel white-noise vector, constant
// over the step, with the discrete variance density^2 / h (the mean of continuous white noise
// over the step, Forster eq. 62); it enters the step like a bias change of opposite sign, and
// is propagated to first order along the same recursion. Summed over many steps this is the
// variance of the continuous model. A position random walk (ImuNoise::integration_density)
// keeps one-step covariances invertible.
//
// Boundaries at arbitrary stamps: a state or a measurement between two samples splits the gap
// it falls in; both parts use that gap's cubic (so an interval ending between samples needs the
// raw sample after its end, which is kept as look-ahead for a later Integrate()).
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
// Requires a.header.stamp_ns <= t_ns <= b.header.stamp_ns and a before b. (A helper for
// callers; the preintegration itself interpolates with the cubic described above.)
ImuSample InterpolateImuSample(const ImuSample& a, const ImuSample& b, TimeNs t_ns);

class ImuPreintegration {
 public:
  ImuPreintegration(const ImuNoise& noise, const ImuBias& bias_lin);

  // Integrates the raw samples (stamps strictly increasing) over exactly [t_begin_ns, t_end_ns]:
  // the signal at the two ends is interpolated when no sample falls on them. The samples must
  // cover the interval (first stamp <= t_begin_ns, last stamp >= t_end_ns); InputError otherwise.
  // Up to two samples before the one at or before t_begin_ns serve as interpolation context.
  static ImuPreintegration FromSamples(std::span<const ImuSample> samples, TimeNs t_begin_ns,
                                       TimeNs t_end_ns, const ImuNoise& noise,
                                       const ImuBias& bias_lin);

  // Adds the raw sample (rad/s, m/s^2 specific force, IMU frame) measured at t_ns. The first
  // sample opens the interval; each later one integrates the step from the previous sample.
  // After FromSamples with an end between two samples, the raw sample after the end is already
  // known (look-ahead): the next call integrates up to it first, and a sample between the end
  // and the look-ahead, or a different one at its stamp, is an InputError.
  // InputError if t_ns does not increase or a value is not finite; the state is then unchanged.
  void Integrate(TimeNs t_ns, const Vec3& gyro, const Vec3& accel);
  void Integrate(const ImuSample& sample) {
    Integrate(sample.header.stamp_ns, sample.gyro, sample.accel);
  }

  // Whether this one starts at t_begin_ns and was integrated with `noise` and `bias_lin` (the
  // biases compared bit for bit).
  bool StartsAs(TimeNs t_begin_ns, const ImuNoise& noise, const ImuBias& bias_lin) const;
  // Whether FromSamples(samples, start_ns(), end_ns(), noise(), bias_lin()) would integrate the
  // very raw samples (bits, stamps, interpolation context) this one holds: it then gives this one
  // bit for bit, when this one came from FromSamples and Integrate at sample stamps. For using
  // a preintegration made from another buffer of the same stream.
  bool IntegratesSamplesOf(std::span<const ImuSample> samples) const;

  // The same raw samples (with their context) integrated again around a new linearisation bias
  // (exact, not first order). Use when the estimated bias moved far from bias_lin().
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
  // Integration nodes: the interval's ends (signal interpolated when between raw samples) and
  // the raw samples inside.
  const std::vector<RawSample>& samples() const { return samples_; }

 private:
  // Integrates from end_ns() to t_ns, both inside the gap (raw_[j-1], raw_[j]], and appends
  // the node at t_ns.
  void Advance(std::size_t j, TimeNs t_ns);

  ImuNoise noise_;
  ImuBias bias_lin_;
  std::vector<RawSample> samples_;  // nodes
  // Raw samples: up to 3 before the interval (context), those inside, and the one at or after
  // its end.
  std::vector<RawSample> raw_;
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
