// The error process of one IMU triad (gyros or accelerometers):
//
//   y = Q( M u + b_turn_on + b_walk + b_gm + n ),   M = I + diag(s) + N_misalignment
//
// u the exact quantity at the sensor axes, s the per-axis scale errors, N the off-diagonal
// cross-axis coupling (small angles), b_walk the bias random walk (Kalibr: one step of sigma
// random_walk * sqrt(dt) per sample, taken before the sample), b_gm a first-order Gauss-Markov
// bias, n white noise of sigma noise_density / sqrt(dt), and Q rounding to the quantisation step.
//
// Every term draws from its own seeded stream ("<name>/white", "<name>/walk", ...), so enabling
// one term does not change the bits of another.
#pragma once

#include <cstdint>
#include <random>
#include <string>

#include "core/eigen_types.hpp"
#include "core/random.hpp"
#include "sensors/gauss_markov.hpp"
#include "sensors/imu_options.hpp"

namespace statebench::sensors {

class ImuTriadErrors {
 public:
  ImuTriadErrors(const ImuTriadOptions& options, double dt_s, std::uint64_t seed,
                 const std::string& stream_name);

  // Advances the bias processes by one sample period and returns the measurement of `exact`.
  Vec3 Measure(const Vec3& exact);

  // Realised per-run errors (for tests and for scoring estimated biases).
  const Mat3& sensitivity() const { return sensitivity_; }  // M
  Vec3 CurrentBias() const { return turn_on_bias_ + walk_bias_ + gauss_markov_.value(); }

 private:
  struct Stream {
    Stream(std::uint64_t seed, const std::string& name) : rng(MakeRng(seed, name)) {}
    std::mt19937_64 rng;
    NormalSampler normal;
    Vec3 Draw() { return Vec3(normal(rng), normal(rng), normal(rng)); }
  };

  ImuTriadOptions options_;
  double white_sigma_ = 0.0;  // per sample
  double walk_step_ = 0.0;    // per sample
  double dt_s_ = 0.0;
  Stream white_;
  Stream walk_;
  Stream gm_;
  Mat3 sensitivity_ = Mat3::Identity();
  Vec3 turn_on_bias_ = Vec3::Zero();
  Vec3 walk_bias_ = Vec3::Zero();
  GaussMarkov3 gauss_markov_;
};

}  // namespace statebench::sensors
