// IMU noise model in Kalibr units (continuous-time densities), as the preintegration uses it.
//
// Discretisation for a sample period dt (Kalibr, REFERENCE.md):
//   white noise of one sample:      sigma_d = density / sqrt(dt)   (variance density^2 / dt)
//   bias random-walk step over dt:  sigma_b = random_walk * sqrt(dt) (variance rw^2 * dt)
// The defaults are industrial MEMS (ADIS16448 class); one default must serve every setup, so
// the estimator is tuned for them and not for a particular sensor.
#pragma once

#include <string>

namespace statebench::est {

struct ImuNoise {
  double gyro_noise_density = 1.7e-4;   // rad/s/sqrt(Hz)
  double accel_noise_density = 2.0e-3;  // m/s^2/sqrt(Hz)
  double gyro_random_walk = 1.9e-5;     // rad/s^2/sqrt(Hz)
  double accel_random_walk = 3.0e-3;    // m/s^3/sqrt(Hz)
  // Not a sensor property: a position random walk (m/sqrt(s)) standing for the discretisation
  // error of position integration. With one sample per interval, position and velocity
  // deltas are driven by the same accelerometer noise and their 9x9 covariance is singular;
  // this small term (1e-6 m over a 10 ms step) keeps it invertible without diluting the
  // information of longer intervals (1e-5 m over 1 s against ~1e-3 m from the accelerometer).
  double integration_density = 1e-5;

  // True if every value is finite and positive (integration_density may be zero). On failure
  // writes the offending field to *why when why is not null.
  bool IsValid(std::string* why = nullptr) const;

  bool operator==(const ImuNoise&) const = default;
};

}  // namespace statebench::est
