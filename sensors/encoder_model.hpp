// Simulated vehicle encoders (options in encoder_options.hpp).
//
// The tick-counting encoders integrate their angle (or distance) from every truth sample with
// the trapezoidal rule and count whole ticks from a random initial phase (seeded), so the
// quantisation error of one sample is below one tick per interval and does not accumulate over
// samples. They emit from their second sample time on (the first only starts the count).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <random>

#include "core/random.hpp"
#include "sensors/encoder_options.hpp"
#include "sensors/sensor_model.hpp"

namespace statebench::sensors {

// Accumulates a continuous quantity and counts ticks of it between sample times.
class TickCounter {
 public:
  TickCounter() = default;
  TickCounter(double tick_size, double initial_phase)
      : tick_size_(tick_size), value_(initial_phase) {}

  // Trapezoidal integration of a rate between two truth samples.
  void Integrate(double rate_prev, double rate_now, double dt_s) {
    value_ += 0.5 * (rate_prev + rate_now) * dt_s;
  }
  // Ticks since the previous Latch call (all ticks since construction on the first call).
  std::int64_t Latch();

 private:
  double tick_size_ = 1.0;
  double value_ = 0.0;
  std::int64_t last_count_ = 0;
};

class WheelEncoderModel : public SensorModel {
 public:
  WheelEncoderModel(const SensorSpec& spec, const WheelEncoderOptions& options, std::uint64_t seed);
  void Observe(const TruthSample& truth, std::vector<Measurement>* out) override;

 private:
  std::array<double, 4> ActualOmega(const TruthSample& truth) const;

  WheelEncoderOptions options_;
  std::array<TickCounter, 4> counters_;
  std::optional<std::array<double, 4>> previous_omega_;
  TimeNs previous_t_ns_ = 0;
  std::optional<TimeNs> last_sample_ns_;
};

class SpeedEncoderModel : public SensorModel {
 public:
  SpeedEncoderModel(const SensorSpec& spec, const SpeedEncoderOptions& options, std::uint64_t seed);
  void Observe(const TruthSample& truth, std::vector<Measurement>* out) override;

 private:
  double ActualSpeed(const TruthSample& truth) const;

  SpeedEncoderOptions options_;
  TickCounter counter_;
  std::optional<double> previous_speed_;
  TimeNs previous_t_ns_ = 0;
  std::optional<TimeNs> last_sample_ns_;
};

class SteeringEncoderModel : public SensorModel {
 public:
  SteeringEncoderModel(const SensorSpec& spec, const SteeringEncoderOptions& options,
                       std::uint64_t seed);
  void Observe(const TruthSample& truth, std::vector<Measurement>* out) override;

 private:
  SteeringEncoderOptions options_;
  std::mt19937_64 rng_;
  NormalSampler normal_;
};

}  // namespace statebench::sensors
