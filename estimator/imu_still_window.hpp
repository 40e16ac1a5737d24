// The newest IMU samples over a fixed span, for the standstill tests (imu_window_statistics.hpp):
// a rolling window that does not depend on when other messages arrive. The low band the tests
// fall back on with an engine running needs 2 taps + 1 samples (21 at 100 Hz and lowpass_s
// 0.1); the ~10 samples between two 10 Hz odometry messages are too few for it, so a test over
// them alone could only pass on the raw samples. The zero-velocity factor, the zero-rate factor
// and the EKF's zero-rate update all test this window (ZeroVelocityOptions::window_s).
#pragma once

#include <deque>
#include <optional>

#include "core/measurements.hpp"
#include "core/time.hpp"
#include "estimator/imu_window_statistics.hpp"
#include "estimator/motion_factor_options.hpp"

namespace statebench::est {

class ImuStillWindow {
 public:
  explicit ImuStillWindow(double window_s)
      : window_ns_(FromSeconds(window_s)), min_span_ns_(FromSeconds(0.9 * window_s)) {}

  // Samples in stamp order; those older than window_s before the newest leave.
  void Push(const ImuSample& s) {
    samples_.push_back(s);
    while (s.header.stamp_ns - samples_.front().header.stamp_ns > window_ns_) samples_.pop_front();
  }
  void Clear() { samples_.clear(); }
  const std::deque<ImuSample>& samples() const { return samples_; }

  // The window's statistics once it spans at least 0.9 window_s (and 3 samples): nullopt before.
  std::optional<ImuWindowStatistics> Statistics(const ZeroVelocityOptions& z) const {
    if (samples_.size() < 3 ||
        samples_.back().header.stamp_ns - samples_.front().header.stamp_ns <
            min_span_ns_) {
      return std::nullopt;
    }
    return ComputeImuWindowStatistics(samples_, z);
  }

 private:
  TimeNs window_ns_;
  TimeNs min_span_ns_;
  std::deque<ImuSample> samples_;
};

// The still test of a span of samples that ends with the window's newest (the samples between
// two odometry messages that read zero): over the span itself when it is at least window_s
// long, else over the rolling window, which covers it; nullopt when neither is long enough.
template <typename Samples>
std::optional<ImuWindowStatistics> StillSpanStatistics(const Samples& span,
                                                       const ImuStillWindow& window,
                                                       const ZeroVelocityOptions& z) {
  if (span.size() >= 3 &&
      span.back().header.stamp_ns - span.front().header.stamp_ns >= FromSeconds(z.window_s)) {
    return ComputeImuWindowStatistics(span, z);
  }
  return window.Statistics(z);
}

}  // namespace statebench::est
