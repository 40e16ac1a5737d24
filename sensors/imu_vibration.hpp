// Mount vibration an IMU measures on a running vehicle (issue 14, "real IMUs"): zero-mean
// oscillations of angular rate and specific force added to the exact motion, before the triad
// errors (imu_triad_errors.hpp), so the IMU's scale and misalignment act on them as on any
// motion. The truth (the rigid body) does not move with them: the displacement is micrometres.
//
//   engine  a combustion engine's harmonics: engine speed idle_rpm + rpm_per_mps v (at most
//           max_rpm); harmonic k of order o_k oscillates at o_k rpm / 60 Hz with the stated rms
//           per axis and a phase drawn per run and axis. Present at standstill (idle).
//   road    broadband body vibration: per axis a unit-variance second-order resonance
//           (frequency_hz, damping) driven by white noise, scaled by rms_per_mps x v, so it
//           vanishes at standstill and rises with speed.
//
// Advanced at every truth step (1 kHz) and sampled at the IMU's stamps, so a harmonic above
// half the IMU rate aliases as it does in a MEMS IMU without an anti-alias filter. Draws from
// its own stream ("<id>/vibration"): turning it on leaves every other error's bits unchanged.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/random.hpp"
#include "sensors/imu_options.hpp"

namespace statebench::sensors {

class ImuVibration {
 public:
  ImuVibration(const ImuVibrationOptions& options, std::uint64_t seed,
               const std::string& stream_name);

  // Moves the vibration on by dt_s at vehicle speed `speed_mps` (>= 0).
  void Advance(double dt_s, double speed_mps);

  const Vec3& gyro_radps() const { return gyro_; }
  const Vec3& accel_mps2() const { return accel_; }
  // Engine speed at the last Advance (0 without an engine).
  double engine_rpm() const { return rpm_; }

 private:
  // Unit-variance AR(2) resonances on three axes (the road term), stationary for a fixed step
  // (exact discretisation of the resonance's poles); coefficients follow the step.
  struct Resonance3 {
    Vec3 y1 = Vec3::Zero(), y2 = Vec3::Zero();  // the last two outputs
  };
  void SetStep(double dt_s);
  void StartStationary(Resonance3* r);
  void Step(Resonance3* r);
  Vec3 Draw() { return Vec3(normal_(rng_), normal_(rng_), normal_(rng_)); }

  ImuVibrationOptions options_;
  std::mt19937_64 rng_;
  NormalSampler normal_;
  std::vector<double> harmonic_phase_;  // per harmonic, advanced with the engine speed
  std::vector<Vec3> axis_phase_;        // per harmonic, per axis, drawn once
  double a1_ = 0.0, a2_ = 0.0, drive_sigma_ = 0.0, step_s_ = 0.0;
  Resonance3 road_gyro_, road_accel_;
  double rpm_ = 0.0;
  Vec3 gyro_ = Vec3::Zero();
  Vec3 accel_ = Vec3::Zero();
};

}  // namespace statebench::sensors
