// An idle engine's vibration for the estimator tests (test fixture): the second and first
// engine orders of an 800 rpm idle (26.7 and 13.3 Hz) with the per-axis rms of the cheap-kit
// setup (scenarios/setups/car_cheap_kit.yaml), each axis with its own seeded phase, added to
// IMU samples; plus white noise of a datasheet density.
#pragma once

#include <array>
#include <cmath>
#include <numbers>
#include <random>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "core/random.hpp"

namespace statebench::est::testing {

struct IdleTone {
  double order2_hz = 800.0 / 60.0 * 2.0;
  double order1_hz = 800.0 / 60.0;
  Vec3 gyro_rms2 = Vec3(0.03, 0.02, 0.015), gyro_rms1 = Vec3(0.005, 0.005, 0.003);
  Vec3 accel_rms2 = Vec3(0.15, 0.10, 0.35), accel_rms1 = Vec3(0.03, 0.03, 0.05);
  std::array<double, 12> phase{};  // [signal (gyro, accel)][order (2, 1)][axis], seeded

  explicit IdleTone(std::uint64_t seed) {
    auto rng = MakeRng(seed, "idle_tone");
    for (double& p : phase) p = 2.0 * std::numbers::pi * Uniform01(rng);
  }

  // Total rms per axis (the two orders are independent sines).
  Vec3 GyroRms() const { return (gyro_rms2.cwiseAbs2() + gyro_rms1.cwiseAbs2()).cwiseSqrt(); }
  Vec3 AccelRms() const { return (accel_rms2.cwiseAbs2() + accel_rms1.cwiseAbs2()).cwiseSqrt(); }

  void Add(double t, ImuSample* s) const {
    const double w2 = 2.0 * std::numbers::pi * order2_hz * t;
    const double w1 = 2.0 * std::numbers::pi * order1_hz * t;
    for (int a = 0; a < 3; ++a) {
      s->gyro[a] += std::sqrt(2.0) * (gyro_rms2[a] * std::sin(w2 + phase[a]) +
                                      gyro_rms1[a] * std::sin(w1 + phase[3 + a]));
      s->accel[a] += std::sqrt(2.0) * (accel_rms2[a] * std::sin(w2 + phase[6 + a]) +
                                       accel_rms1[a] * std::sin(w1 + phase[9 + a]));
    }
  }
};

}  // namespace statebench::est::testing
