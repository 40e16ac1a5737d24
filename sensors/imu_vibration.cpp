#include "sensors/imu_vibration.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace statebench::sensors {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kDefaultStepS = 1e-3;  // the truth's step

}  // namespace

ImuVibration::ImuVibration(const ImuVibrationOptions& options, std::uint64_t seed,
                           const std::string& stream_name)
    : options_(options), rng_(MakeRng(seed, stream_name)) {
  if (options_.engine) {
    std::uniform_real_distribution<double> phase(0.0, kTwoPi);
    for (std::size_t k = 0; k < options_.engine->harmonics.size(); ++k) {
      harmonic_phase_.push_back(0.0);
      axis_phase_.emplace_back(phase(rng_), phase(rng_), phase(rng_));
    }
  }
  if (options_.road) {
    SetStep(kDefaultStepS);
    StartStationary(&road_gyro_);
    StartStationary(&road_accel_);
  }
  Advance(0.0, 0.0);
}

void ImuVibration::SetStep(double dt_s) {
  // Poles of the continuous resonance x'' + 2 z w x' + w^2 x at r e^(+-i theta) after dt_s:
  // y_k = a1 y_k-1 + a2 y_k-2 + e_k, whose stationary variance is
  // s^2 (1 - a2) / ((1 + a2) ((1 - a2)^2 - a1^2)); s is chosen to make it 1.
  const RoadVibrationOptions& o = *options_.road;
  const double w = kTwoPi * o.frequency_hz;
  const double r = std::exp(-o.damping * w * dt_s);
  const double theta = w * std::sqrt(1.0 - o.damping * o.damping) * dt_s;
  a1_ = 2.0 * r * std::cos(theta);
  a2_ = -r * r;
  const double gain = (1.0 - a2_) / ((1.0 + a2_) * ((1.0 - a2_) * (1.0 - a2_) - a1_ * a1_));
  drive_sigma_ = 1.0 / std::sqrt(gain);
  step_s_ = dt_s;
}

void ImuVibration::StartStationary(Resonance3* r) {
  // Lag-one correlation of the stationary AR(2): a1 / (1 - a2).
  const double rho = a1_ / (1.0 - a2_);
  r->y2 = Draw();
  r->y1 = rho * r->y2 + std::sqrt(std::max(0.0, 1.0 - rho * rho)) * Draw();
}

void ImuVibration::Step(Resonance3* r) {
  const Vec3 y = a1_ * r->y1 + a2_ * r->y2 + drive_sigma_ * Draw();
  r->y2 = r->y1;
  r->y1 = y;
}

void ImuVibration::Advance(double dt_s, double speed_mps) {
  gyro_.setZero();
  accel_.setZero();
  if (options_.engine) {
    const EngineVibrationOptions& e = *options_.engine;
    rpm_ = std::min(e.max_rpm, e.idle_rpm + e.rpm_per_mps * std::max(0.0, speed_mps));
    for (std::size_t k = 0; k < e.harmonics.size(); ++k) {
      const EngineHarmonic& h = e.harmonics[k];
      harmonic_phase_[k] = std::fmod(harmonic_phase_[k] + kTwoPi * h.order * rpm_ / 60.0 * dt_s,
                                     kTwoPi);
      for (int axis = 0; axis < 3; ++axis) {
        const double wave = std::numbers::sqrt2 * std::sin(harmonic_phase_[k] + axis_phase_[k](axis));
        gyro_(axis) += h.gyro_rms_radps(axis) * wave;
        accel_(axis) += h.accel_rms_mps2(axis) * wave;
      }
    }
  }
  if (options_.road) {
    if (dt_s > 0.0) {
      if (std::abs(dt_s - step_s_) > 1e-12) SetStep(dt_s);
      Step(&road_gyro_);
      Step(&road_accel_);
    }
    const double v = std::max(0.0, speed_mps);
    gyro_ += v * options_.road->gyro_rms_per_mps.cwiseProduct(road_gyro_.y1);
    accel_ += v * options_.road->accel_rms_per_mps.cwiseProduct(road_accel_.y1);
  }
}

}  // namespace statebench::sensors
