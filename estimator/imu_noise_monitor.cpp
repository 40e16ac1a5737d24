#include "estimator/imu_noise_monitor.hpp"

#include <algorithm>
#include <cmath>

#include <vector>

namespace statebench::est {
namespace {

// Hadamard variance of the means over consecutive spans of `span` samples, per axis, averaged
// over the axes: (1/6) E[(m[k+1] - 2 m[k] + m[k-1])^2]; 0 with fewer than 3 spans.
double MeanAxisHadamardVariance(const std::vector<ImuSample>& block, int span, bool gyro) {
  std::vector<Vec3> means;
  for (std::size_t i = 0; i + span <= block.size(); i += span) {
    Vec3 sum = Vec3::Zero();
    for (int j = 0; j < span; ++j) sum += gyro ? block[i + j].gyro : block[i + j].accel;
    means.push_back(sum / span);
  }
  if (means.size() < 3) return 0.0;
  Vec3 sum = Vec3::Zero();
  for (std::size_t k = 1; k + 1 < means.size(); ++k) {
    sum += (means[k + 1] - 2.0 * means[k] + means[k - 1]).cwiseAbs2();
  }
  return sum.mean() / (6.0 * static_cast<double>(means.size() - 2));
}

}  // namespace

ImuNoiseMonitor::ImuNoiseMonitor(const ImuNoiseEstimationOptions& options,
                                 const ImuNoise& configured)
    : options_(options), configured_(configured), used_(configured) {
  report_.enabled = options.enabled;
  report_.gyro_configured = report_.gyro_used = report_.gyro_used_max =
      configured.gyro_noise_density;
  report_.accel_configured = report_.accel_used = report_.accel_used_max =
      configured.accel_noise_density;
}

bool ImuNoiseMonitor::AddStill(const ImuSample& sample) {
  if (!options_.enabled) return false;
  const TimeNs t = sample.header.stamp_ns;
  if (last_ns_) {
    if (t <= *last_ns_) return false;  // taken with an earlier still window
    // A gap (the vehicle moved, or samples are missing) breaks the block: the means assume a
    // constant rate and a still vehicle throughout.
    if (period_ns_ > 0 && t - *last_ns_ > 2 * period_ns_) {
      block_.clear();
    } else {
      period_ns_ = t - *last_ns_;
    }
  }
  last_ns_ = t;
  block_.push_back(sample);
  if (sample.header.stamp_ns - block_.front().header.stamp_ns < FromSeconds(options_.block_s)) {
    return false;
  }
  const ImuNoise before = used_;
  CloseBlock();
  block_.clear();
  return used_.gyro_noise_density != before.gyro_noise_density ||
         used_.accel_noise_density != before.accel_noise_density;
}

void ImuNoiseMonitor::CloseBlock() {
  const double dt = ToSeconds(block_.back().header.stamp_ns - block_.front().header.stamp_ns) /
                    static_cast<double>(block_.size() - 1);
  const int span = std::max(1, static_cast<int>(std::lround(options_.scale_s / dt)));
  if (block_.size() < 3 * static_cast<std::size_t>(span)) return;
  const double T = span * dt;
  const double alpha = 1.0 - std::exp(-options_.block_s / options_.time_constant_s);
  const auto update = [&](std::optional<double>& mean, bool gyro) {
    const double density2 = MeanAxisHadamardVariance(block_, span, gyro) * T;
    mean = mean ? *mean + alpha * (density2 - *mean) : density2;
    return std::sqrt(*mean);
  };
  report_.gyro_measured = update(gyro_variance_density_, true);
  report_.accel_measured = update(accel_variance_density_, false);
  ++report_.blocks;
  used_.gyro_noise_density = Used(report_.gyro_measured, configured_.gyro_noise_density);
  used_.accel_noise_density = Used(report_.accel_measured, configured_.accel_noise_density);
  report_.gyro_used = used_.gyro_noise_density;
  report_.accel_used = used_.accel_noise_density;
  report_.gyro_used_max = std::max(report_.gyro_used_max, report_.gyro_used);
  report_.accel_used_max = std::max(report_.accel_used_max, report_.accel_used);
}

double ImuNoiseMonitor::Used(double measured, double configured) const {
  if (!(measured > options_.inflate_above * configured)) return configured;
  return std::min(measured, options_.max_inflation * configured);
}

}  // namespace statebench::est
