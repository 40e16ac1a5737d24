#include "estimator/state_estimate.hpp"

#include <cmath>

namespace statebench::est {

std::optional<StateEstimate> ToStateEstimate(const PropagatedState& p, const LocalEnuFrame& frame) {
  StateEstimate out;
  out.state = p.state;
  out.covariance = p.covariance;
  const GeodeticPoint g = frame.ToGeodetic(out.state.p_world);
  out.latitude_deg = g.latitude_deg;
  out.longitude_deg = g.longitude_deg;
  out.altitude_m = g.altitude_m;
  const NavState& s = out.state;
  if (!s.q_world_imu.coeffs().allFinite() || !s.p_world.allFinite() || !s.v_world.allFinite() ||
      !s.gyro_bias.allFinite() || !s.accel_bias.allFinite() || !out.covariance.allFinite() ||
      !std::isfinite(out.latitude_deg) || !std::isfinite(out.longitude_deg)) {
    return std::nullopt;
  }
  return out;
}

}  // namespace statebench::est
