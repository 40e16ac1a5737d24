#include "sensors/sensor_spec.hpp"

#include <cmath>

namespace statebench::sensors {

bool RateDividesTruthRate(double rate_hz) {
  if (!std::isfinite(rate_hz) || rate_hz <= 0.0) return false;
  const double period_ns = 1e9 / rate_hz;
  const double rounded = std::round(period_ns);
  if (std::abs(period_ns - rounded) > 1e-3) return false;
  const auto p = static_cast<TimeNs>(rounded);
  return p >= kTruthPeriodNs && p % kTruthPeriodNs == 0;
}

}  // namespace statebench::sensors
