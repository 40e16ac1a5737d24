#include "sensors/log_csv.hpp"

#include <type_traits>

namespace statebench::sensors {
namespace {

void Comma(std::string& out, double v) {
  out += ',';
  AppendNumber(out, v);
}

void Comma(std::string& out, std::int64_t v) {
  out += ',';
  AppendNumber(out, v);
}

void AppendStamps(std::string& out, const MeasurementHeader& h) {
  AppendNumber(out, h.stamp_ns);
  Comma(out, h.arrival_ns);
}

MeasurementHeader HeaderFrom(const std::string& id, const CsvRow& row, StampColumns c) {
  return MeasurementHeader{id, row.Int(c.stamp), row.Int(c.arrival)};
}

}  // namespace

StampColumns StampColumnsOf(LogStreamType type) {
  return type == LogStreamType::kImu ? StampColumns{0, 7} : StampColumns{0, 1};
}

void AppendLogCsvRow(std::string& out, const Measurement& m) {
  std::visit(
      [&out](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, ImuSample>) {
          AppendNumber(out, x.header.stamp_ns);
          for (int i = 0; i < 3; ++i) Comma(out, x.gyro[i]);
          for (int i = 0; i < 3; ++i) Comma(out, x.accel[i]);
          Comma(out, x.header.arrival_ns);
        } else if constexpr (std::is_same_v<T, GnssFix>) {
          AppendStamps(out, x.header);
          Comma(out, x.latitude_deg);
          Comma(out, x.longitude_deg);
          Comma(out, x.altitude_m);
          for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) Comma(out, x.covariance_enu(r, c));
          }
          out += ',';
          out += GnssStatusName(x.status);
        } else if constexpr (std::is_same_v<T, DualAntennaHeading>) {
          AppendStamps(out, x.header);
          Comma(out, x.yaw_rad);
          Comma(out, x.pitch_rad);
          Comma(out, x.yaw_sigma_rad);
          Comma(out, x.pitch_sigma_rad);
        } else if constexpr (std::is_same_v<T, WheelSpeeds>) {
          AppendStamps(out, x.header);
          for (double w : x.omega_radps) Comma(out, w);
        } else if constexpr (std::is_same_v<T, VehicleSpeed>) {
          AppendStamps(out, x.header);
          Comma(out, x.speed_mps);
        } else if constexpr (std::is_same_v<T, SteeringAngle>) {
          AppendStamps(out, x.header);
          Comma(out, x.angle_rad);
        } else if constexpr (std::is_same_v<T, BodyVelocity>) {
          AppendStamps(out, x.header);
          for (int i = 0; i < 3; ++i) Comma(out, x.velocity[i]);
          for (int i = 0; i < 3; ++i) Comma(out, x.angular_velocity[i]);
          for (int r = 0; r < 6; ++r) {
            for (int c = 0; c < 6; ++c) Comma(out, x.covariance(r, c));
          }
        } else {
          static_assert(std::is_same_v<T, LidarScan>);
          out += "lidar scans go to PCD files";  // never reached: LogWriter routes them
        }
      },
      m);
  out += '\n';
}

void AppendLidarIndexRow(std::string& out, const LidarScan& scan, std::string_view pcd_file) {
  AppendStamps(out, scan.header);
  Comma(out, static_cast<std::int64_t>(scan.points ? scan.points->size() : 0));
  out += ',';
  out += pcd_file;
  out += '\n';
}

void CheckColumnCount(LogStreamType type, const CsvRow& row) {
  const std::size_t expected = LogCsvColumns(type).size();
  if (row.size() > expected) {
    row.Fail(expected,
             "unexpected extra value (the file has " + std::to_string(expected) + " columns)");
  }
  if (row.size() < expected) row.Fail(row.size(), "missing value");
}

Measurement ParseLogCsvRow(LogStreamType type, const std::string& id, const CsvRow& row) {
  CheckColumnCount(type, row);
  const MeasurementHeader header = HeaderFrom(id, row, StampColumnsOf(type));
  switch (type) {
    case LogStreamType::kImu: {
      ImuSample s{header};
      for (int i = 0; i < 3; ++i) s.gyro[i] = row.Double(1 + i);
      for (int i = 0; i < 3; ++i) s.accel[i] = row.Double(4 + i);
      return s;
    }
    case LogStreamType::kGnss: {
      GnssFix f{header};
      f.latitude_deg = row.Double(2);
      f.longitude_deg = row.Double(3);
      f.altitude_m = row.Double(4);
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) f.covariance_enu(r, c) = row.Double(5 + 3 * r + c);
      }
      const auto status = ParseGnssStatus(row.Text(14));
      if (!status) {
        row.Fail(14, "unknown status '" + std::string(row.Text(14)) +
                         "' (expected none, single, rtk_float or rtk_fixed)");
      }
      f.status = *status;
      return f;
    }
    case LogStreamType::kDualAntennaHeading: {
      DualAntennaHeading h{header};
      h.yaw_rad = row.Double(2);
      h.pitch_rad = row.Double(3);
      h.yaw_sigma_rad = row.Double(4);
      h.pitch_sigma_rad = row.Double(5);
      return h;
    }
    case LogStreamType::kWheelSpeeds: {
      WheelSpeeds w{header};
      for (std::size_t i = 0; i < 4; ++i) w.omega_radps[i] = row.Double(2 + i);
      return w;
    }
    case LogStreamType::kVehicleSpeed:
      return VehicleSpeed{header, row.Double(2)};
    case LogStreamType::kSteeringAngle:
      return SteeringAngle{header, row.Double(2)};
    case LogStreamType::kBodyVelocity: {
      BodyVelocity b{header};
      for (int i = 0; i < 3; ++i) b.velocity[i] = row.Double(2 + i);
      for (int i = 0; i < 3; ++i) b.angular_velocity[i] = row.Double(5 + i);
      for (int r = 0; r < 6; ++r) {
        for (int c = 0; c < 6; ++c) b.covariance(r, c) = row.Double(8 + 6 * r + c);
      }
      return b;
    }
    case LogStreamType::kLidar:
      break;
  }
  row.Fail(0, "lidar index rows are read by the lidar stream");
}

}  // namespace statebench::sensors
