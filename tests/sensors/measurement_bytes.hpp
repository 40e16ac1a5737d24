// Every field of a measurement as raw bytes (lidar points field by field, never their padding),
// for bit-exact comparisons of measurement streams.
#pragma once

#include <string>
#include <type_traits>
#include <variant>

#include "core/measurements.hpp"

namespace statebench::testing {

template <typename T>
void AppendRawBytes(const T& value, std::string* out) {
  const auto* p = reinterpret_cast<const char*>(&value);
  out->append(p, p + sizeof(T));
}

inline std::string MeasurementBytes(const Measurement& m) {
  std::string out;
  const MeasurementHeader& h = HeaderOf(m);
  AppendRawBytes(m.index(), &out);
  out += h.sensor_id;
  out += '\0';
  AppendRawBytes(h.stamp_ns, &out);
  AppendRawBytes(h.arrival_ns, &out);
  std::visit(
      [&out](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, ImuSample>) {
          AppendRawBytes(x.gyro, &out);
          AppendRawBytes(x.accel, &out);
        } else if constexpr (std::is_same_v<T, GnssFix>) {
          AppendRawBytes(x.latitude_deg, &out);
          AppendRawBytes(x.longitude_deg, &out);
          AppendRawBytes(x.altitude_m, &out);
          AppendRawBytes(x.covariance_enu, &out);
          AppendRawBytes(x.status, &out);
          out += x.velocity ? 'v' : '-';
          if (x.velocity) {
            AppendRawBytes(x.velocity->v_enu, &out);
            AppendRawBytes(x.velocity->sigma_enu, &out);
          }
        } else if constexpr (std::is_same_v<T, DualAntennaHeading>) {
          AppendRawBytes(x.yaw_rad, &out);
          AppendRawBytes(x.pitch_rad, &out);
          AppendRawBytes(x.yaw_sigma_rad, &out);
          AppendRawBytes(x.pitch_sigma_rad, &out);
        } else if constexpr (std::is_same_v<T, WheelSpeeds>) {
          AppendRawBytes(x.omega_radps, &out);
        } else if constexpr (std::is_same_v<T, VehicleSpeed>) {
          AppendRawBytes(x.speed_mps, &out);
        } else if constexpr (std::is_same_v<T, SteeringAngle>) {
          AppendRawBytes(x.angle_rad, &out);
        } else if constexpr (std::is_same_v<T, BodyVelocity>) {
          AppendRawBytes(x.velocity, &out);
          AppendRawBytes(x.angular_velocity, &out);
          AppendRawBytes(x.covariance, &out);
        } else {
          static_assert(std::is_same_v<T, LidarScan>);
          const std::size_t n = x.points ? x.points->size() : 0;
          AppendRawBytes(n, &out);
          for (std::size_t i = 0; i < n; ++i) {
            const LidarPoint& p = (*x.points)[i];
            AppendRawBytes(p.x, &out);
            AppendRawBytes(p.y, &out);
            AppendRawBytes(p.z, &out);
            AppendRawBytes(p.intensity, &out);
            AppendRawBytes(p.t, &out);
            AppendRawBytes(p.ring, &out);
          }
        }
      },
      m);
  return out;
}

}  // namespace statebench::testing
