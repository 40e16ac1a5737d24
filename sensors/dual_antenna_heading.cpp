#include "sensors/dual_antenna_heading.hpp"

#include <cmath>

namespace statebench::sensors {

std::optional<DualAntennaHeading> ComputeDualAntennaHeading(
    const DualAntennaHeadingOptions& options, const GnssFix& main, const GnssFix& aux,
    const LocalEnuFrame& frame) {
  if (main.header.stamp_ns != aux.header.stamp_ns) return std::nullopt;
  if (static_cast<int>(main.status) < static_cast<int>(options.min_status) ||
      static_cast<int>(aux.status) < static_cast<int>(options.min_status)) {
    return std::nullopt;
  }
  const Vec3 p_main = frame.ToEnu({main.latitude_deg, main.longitude_deg, main.altitude_m});
  const Vec3 p_aux = frame.ToEnu({aux.latitude_deg, aux.longitude_deg, aux.altitude_m});
  const Vec3 b = p_aux - p_main;
  const double horizontal = std::hypot(b.x(), b.y());
  const double length = b.norm();
  if (horizontal <= 0.0) return std::nullopt;

  // First-order propagation: d(yaw)/db = u_perp / |b_h| with u_perp the horizontal unit normal
  // to b; d(elevation)/db = w / |b| with w the unit vector normal to b in its vertical plane.
  const Mat3 cov = main.covariance_enu + aux.covariance_enu;
  const Vec3 u_perp(-b.y() / horizontal, b.x() / horizontal, 0.0);
  const Vec3 w =
      (Vec3(-b.z() * b.x() / horizontal, -b.z() * b.y() / horizontal, horizontal)) / length;

  DualAntennaHeading h;
  h.header.sensor_id = options.id;
  h.header.stamp_ns = main.header.stamp_ns;
  h.header.arrival_ns = main.header.stamp_ns + FromSeconds(options.latency_s);
  h.yaw_rad = std::atan2(b.y(), b.x());
  h.pitch_rad = std::atan2(-b.z(), horizontal);
  h.yaw_sigma_rad = std::sqrt(u_perp.dot(cov * u_perp)) / horizontal;
  h.pitch_sigma_rad = std::sqrt(w.dot(cov * w)) / length;
  return h;
}

}  // namespace statebench::sensors
