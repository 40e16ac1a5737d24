// Error parameters of a simulated IMU, in Kalibr units (DESIGN.md):
//   noise_density  gyro rad/s/sqrt(Hz),   accel m/s^2/sqrt(Hz)
//   random_walk    gyro rad/s^2/sqrt(Hz), accel m/s^3/sqrt(Hz)
// Discretised for a sample period dt: white sigma = noise_density / sqrt(dt); bias step sigma =
// random_walk * sqrt(dt).
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "core/eigen_types.hpp"

namespace statebench::sensors {

// Errors of one sensor triad (the gyros or the accelerometers). Units are those of the triad
// (rad/s or m/s^2). A zero disables the term.
struct ImuTriadOptions {
  double noise_density = 0.0;
  double random_walk = 0.0;
  double turn_on_bias_sigma = 0.0;      // constant bias, drawn once per run per axis
  double gauss_markov_sigma = 0.0;      // stationary sigma of a first-order Gauss-Markov bias
  double gauss_markov_tau_s = 1000.0;   // its time constant
  double scale_factor_sigma = 0.0;      // relative scale error, drawn once per axis
  double misalignment_sigma_rad = 0.0;  // cross-axis coupling, drawn once per off-diagonal term
  double quantization = 0.0;            // output resolution (one LSB); 0 = continuous
};

// Mount vibration (imu_vibration.hpp has the model).
struct EngineHarmonic {
  double order = 2.0;                  // multiple of the engine speed (2: a 4-cylinder's firing)
  Vec3 gyro_rms_radps = Vec3::Zero();  // per IMU axis
  Vec3 accel_rms_mps2 = Vec3::Zero();
};

struct EngineVibrationOptions {
  double idle_rpm = 800.0;
  double rpm_per_mps = 100.0;  // engine speed rises with vehicle speed (one gear, no slip)
  double max_rpm = 3000.0;
  std::vector<EngineHarmonic> harmonics;
};

struct RoadVibrationOptions {
  Vec3 gyro_rms_per_mps = Vec3::Zero();   // rad/s rms per m/s of speed, per axis
  Vec3 accel_rms_per_mps = Vec3::Zero();  // m/s^2 rms per m/s of speed, per axis
  double frequency_hz = 12.0;             // the body's resonance on its suspension
  double damping = 0.3;                   // damping ratio, in (0, 1)
};

struct ImuVibrationOptions {
  std::optional<EngineVibrationOptions> engine;
  std::optional<RoadVibrationOptions> road;
};

struct ImuOptions {
  ImuTriadOptions gyro;
  ImuTriadOptions accel;
  ImuVibrationOptions vibration;  // none by default
};

enum class ImuGrade { kConsumer, kIndustrial, kTactical };

// Presets (REFERENCE.md for densities and random walks; turn-on bias, scale factor,
// misalignment and quantisation are typical datasheet magnitudes of each class, not a
// particular part). No preset enables the Gauss-Markov bias.
ImuOptions ImuPreset(ImuGrade grade);
std::optional<ImuGrade> ParseImuGrade(std::string_view name);  // consumer|industrial|tactical

}  // namespace statebench::sensors
