#include "sensors/encoder_model.hpp"

#include <cmath>
#include <numbers>

namespace statebench::sensors {

std::int64_t TickCounter::Latch() {
  const auto count = static_cast<std::int64_t>(std::floor(value_ / tick_size_));
  const std::int64_t ticks = count - last_count_;
  last_count_ = count;
  return ticks;
}

// --- wheel encoders -------------------------------------------------------------------------

WheelEncoderModel::WheelEncoderModel(const SensorSpec& spec, const WheelEncoderOptions& options,
                                     std::uint64_t seed)
    : SensorModel(spec), options_(options) {
  std::mt19937_64 rng = MakeRng(seed, spec.id + "/phase");
  const double tick = 2.0 * std::numbers::pi / options.ticks_per_rev;
  for (auto& c : counters_) c = TickCounter(tick, tick * Uniform01(rng));
}

std::array<double, 4> WheelEncoderModel::ActualOmega(const TruthSample& truth) const {
  std::array<double, 4> omega{};
  for (int i = 0; i < 4; ++i)
    omega[i] = truth.wheel_omega_radps[i] / (1.0 + options_.radius_error[i]);
  return omega;
}

void WheelEncoderModel::Observe(const TruthSample& truth, std::vector<Measurement>* out) {
  const std::array<double, 4> omega = ActualOmega(truth);
  if (previous_omega_) {
    const double dt_s = ToSeconds(truth.t_ns - previous_t_ns_);
    for (int i = 0; i < 4; ++i) counters_[i].Integrate((*previous_omega_)[i], omega[i], dt_s);
  }
  previous_omega_ = omega;
  previous_t_ns_ = truth.t_ns;
  if (!spec().IsSampleTime(truth.t_ns)) return;

  std::array<std::int64_t, 4> ticks{};
  for (int i = 0; i < 4; ++i) ticks[i] = counters_[i].Latch();
  if (last_sample_ns_) {
    const double interval_s = ToSeconds(truth.t_ns - *last_sample_ns_);
    const double tick = 2.0 * std::numbers::pi / options_.ticks_per_rev;
    WheelSpeeds m;
    m.header = MakeHeader(truth.t_ns);
    for (int i = 0; i < 4; ++i)
      m.omega_radps[i] = static_cast<double>(ticks[i]) * tick / interval_s;
    out->push_back(m);
  }
  last_sample_ns_ = truth.t_ns;
}

// --- speed encoder --------------------------------------------------------------------------

SpeedEncoderModel::SpeedEncoderModel(const SensorSpec& spec, const SpeedEncoderOptions& options,
                                     std::uint64_t seed)
    : SensorModel(spec), options_(options) {
  std::mt19937_64 rng = MakeRng(seed, spec.id + "/phase");
  counter_ = TickCounter(options.distance_per_tick_m, options.distance_per_tick_m * Uniform01(rng));
}

double SpeedEncoderModel::ActualSpeed(const TruthSample& truth) const {
  // Velocity of the mount point along the mount's x axis (lever-arm term included).
  const double v_x = truth.body.AtMount(spec().T_body_sensor).VelocityInFrame().x();
  return v_x / (1.0 + options_.radius_error);
}

void SpeedEncoderModel::Observe(const TruthSample& truth, std::vector<Measurement>* out) {
  const double speed = ActualSpeed(truth);
  if (previous_speed_) {
    counter_.Integrate(*previous_speed_, speed, ToSeconds(truth.t_ns - previous_t_ns_));
  }
  previous_speed_ = speed;
  previous_t_ns_ = truth.t_ns;
  if (!spec().IsSampleTime(truth.t_ns)) return;

  const std::int64_t ticks = counter_.Latch();
  if (last_sample_ns_) {
    VehicleSpeed m;
    m.header = MakeHeader(truth.t_ns);
    m.speed_mps = static_cast<double>(ticks) * options_.distance_per_tick_m /
                  ToSeconds(truth.t_ns - *last_sample_ns_);
    out->push_back(m);
  }
  last_sample_ns_ = truth.t_ns;
}

// --- steering encoder -----------------------------------------------------------------------

SteeringEncoderModel::SteeringEncoderModel(const SensorSpec& spec,
                                           const SteeringEncoderOptions& options,
                                           std::uint64_t seed)
    : SensorModel(spec), options_(options), rng_(MakeRng(seed, spec.id + "/white")) {}

void SteeringEncoderModel::Observe(const TruthSample& truth, std::vector<Measurement>* out) {
  if (!spec().IsSampleTime(truth.t_ns)) return;
  double angle = truth.steering_front_rad + options_.offset_rad;
  if (options_.noise_sigma_rad > 0.0) angle += options_.noise_sigma_rad * normal_(rng_);
  if (options_.resolution_rad > 0.0) {
    angle = std::round(angle / options_.resolution_rad) * options_.resolution_rad;
  }
  SteeringAngle m;
  m.header = MakeHeader(truth.t_ns);
  m.angle_rad = angle;
  out->push_back(m);
}

}  // namespace statebench::sensors
