#include "sensors/imu_triad_errors.hpp"

#include <cmath>

namespace statebench::sensors {
namespace {

double Quantize(double value, double step) {
  return step > 0.0 ? std::round(value / step) * step : value;
}

}  // namespace

ImuTriadErrors::ImuTriadErrors(const ImuTriadOptions& options, double dt_s, std::uint64_t seed,
                               const std::string& stream_name)
    : options_(options),
      white_sigma_(options.noise_density / std::sqrt(dt_s)),
      walk_step_(options.random_walk * std::sqrt(dt_s)),
      dt_s_(dt_s),
      white_(seed, stream_name + "/white"),
      walk_(seed, stream_name + "/walk"),
      gm_(seed, stream_name + "/gauss_markov") {
  // Per-run constants, drawn in a fixed order from their own stream.
  Stream constants(seed, stream_name + "/constants");
  turn_on_bias_ = options.turn_on_bias_sigma * constants.Draw();
  const Vec3 scale = options.scale_factor_sigma * constants.Draw();
  const Vec3 upper = options.misalignment_sigma_rad * constants.Draw();
  const Vec3 lower = options.misalignment_sigma_rad * constants.Draw();
  sensitivity_ << 1.0 + scale.x(), upper.x(), upper.y(),  //
      lower.x(), 1.0 + scale.y(), upper.z(),              //
      lower.y(), lower.z(), 1.0 + scale.z();
  if (options.gauss_markov_sigma > 0.0) {
    gauss_markov_ =
        GaussMarkov3(options.gauss_markov_sigma, options.gauss_markov_tau_s, gm_.rng, gm_.normal);
  }
}

Vec3 ImuTriadErrors::Measure(const Vec3& exact) {
  if (walk_step_ > 0.0) walk_bias_ += walk_step_ * walk_.Draw();
  if (options_.gauss_markov_sigma > 0.0) gauss_markov_.Step(dt_s_, gm_.rng, gm_.normal);
  Vec3 y = sensitivity_ * exact + CurrentBias();
  if (white_sigma_ > 0.0) y += white_sigma_ * white_.Draw();
  for (int i = 0; i < 3; ++i) y[i] = Quantize(y[i], options_.quantization);
  return y;
}

}  // namespace statebench::sensors
