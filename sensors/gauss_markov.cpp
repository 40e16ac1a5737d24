#include "sensors/gauss_markov.hpp"

#include <cmath>

namespace statebench::sensors {

GaussMarkov3::GaussMarkov3(double sigma, double tau_s, std::mt19937_64& rng, NormalSampler& normal)
    : sigma_(sigma), tau_s_(tau_s) {
  for (int i = 0; i < 3; ++i) x_[i] = sigma_ * normal(rng);
}

const Vec3& GaussMarkov3::Step(double dt_s, std::mt19937_64& rng, NormalSampler& normal) {
  const double phi = std::exp(-dt_s / tau_s_);
  // 1 - phi^2 computed as -expm1(-2 dt / tau) keeps precision when dt << tau.
  const double drive = sigma_ * std::sqrt(-std::expm1(-2.0 * dt_s / tau_s_));
  for (int i = 0; i < 3; ++i) x_[i] = phi * x_[i] + drive * normal(rng);
  return x_;
}

}  // namespace statebench::sensors
