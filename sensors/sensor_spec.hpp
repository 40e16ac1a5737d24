// What every sensor of a setup has, whatever its type: an id, a sampling rate, a static mount on
// the vehicle body and a latency.
//
// Sampling: truth comes at 1 kHz (kTruthPeriodNs) and a sensor samples at the truth stamps that
// are multiples of its period, t_k = k * period. Rates must therefore divide 1000 Hz; the setup
// loader rejects other rates. Arrival = stamp + latency.
#pragma once

#include <string>

#include "core/se3.hpp"
#include "core/time.hpp"

namespace statebench::sensors {

inline constexpr TimeNs kTruthPeriodNs = kNsPerMillisecond;

struct SensorSpec {
  std::string id;
  double rate_hz = 100.0;
  SE3 T_body_sensor;  // body frame: FLU, origin on the road below the centre of gravity
  double latency_s = 0.0;

  TimeNs PeriodNs() const { return FromSeconds(1.0 / rate_hz); }
  TimeNs LatencyNs() const { return FromSeconds(latency_s); }
  bool IsSampleTime(TimeNs t_ns) const { return t_ns % PeriodNs() == 0; }
};

// True when 1/rate_hz is a whole number of truth periods (1 ms), e.g. 1, 2, 4, 5, 8, 10, 20,
// 25, 40, 50, 100, 125, 200, 250, 500, 1000 Hz.
bool RateDividesTruthRate(double rate_hz);

}  // namespace statebench::sensors
