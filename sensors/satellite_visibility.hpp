// Hook for an urban-canyon model: how many satellites an antenna sees. The receiver degrades its
// fix with the count (GnssSatelliteThresholds): fixed -> float -> single -> no fix. Without a
// model every satellite is visible and the receiver keeps its configured mode.
#pragma once

#include "core/eigen_types.hpp"
#include "core/time.hpp"

namespace statebench::sensors {

class SatelliteVisibility {
 public:
  virtual ~SatelliteVisibility() = default;
  // Number of satellites in line of sight from the antenna phase centre p_world_antenna (local
  // ENU world frame, m) at t_ns. Called from the simulation thread, once per fix per antenna.
  virtual int VisibleSatellites(const Vec3& p_world_antenna, TimeNs t_ns) const = 0;
};

}  // namespace statebench::sensors
