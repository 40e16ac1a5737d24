// Time in StateBench: int64 nanoseconds everywhere a stamp is stored.
#pragma once

#include <cmath>
#include <cstdint>

namespace statebench {

using TimeNs = std::int64_t;

inline constexpr TimeNs kNsPerSecond = 1'000'000'000;
inline constexpr TimeNs kNsPerMillisecond = 1'000'000;

inline constexpr double ToSeconds(TimeNs t_ns) { return static_cast<double>(t_ns) * 1e-9; }

// Rounds to the nearest nanosecond (half away from zero).
inline TimeNs FromSeconds(double t_s) { return static_cast<TimeNs>(std::llround(t_s * 1e9)); }

}  // namespace statebench
