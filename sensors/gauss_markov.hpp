// First-order Gauss-Markov process on three independent axes, exactly discretised:
//
//   dx/dt = -x / tau + w,   stationary standard deviation sigma,
//   x(t + dt) = phi x(t) + sigma sqrt(1 - phi^2) n,   phi = exp(-dt / tau),  n ~ N(0, 1).
//
// The discretisation is exact for any dt, so irregular steps (a receiver after an outage) keep
// the process statistics. The state starts from its stationary distribution N(0, sigma^2).
#pragma once

#include <random>

#include "core/eigen_types.hpp"
#include "core/random.hpp"

namespace statebench::sensors {

class GaussMarkov3 {
 public:
  GaussMarkov3() = default;
  GaussMarkov3(double sigma, double tau_s, std::mt19937_64& rng, NormalSampler& normal);

  const Vec3& Step(double dt_s, std::mt19937_64& rng, NormalSampler& normal);
  const Vec3& value() const { return x_; }

 private:
  double sigma_ = 0.0;
  double tau_s_ = 1.0;
  Vec3 x_ = Vec3::Zero();
};

}  // namespace statebench::sensors
