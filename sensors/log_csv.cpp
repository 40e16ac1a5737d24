#include "sensors/log_csv.hpp"

#include <cassert>
#include <type_traits>

#include "core/error.hpp"

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

constexpr std::size_t kGnssVelocityColumn = 15;  // after status

void AppendGnssVelocity(std::string& out, const std::optional<GnssVelocity>& v) {
  if (!v) {
    out += ",,,,,,";
    return;
  }
  for (int i = 0; i < 3; ++i) Comma(out, v->v_enu[i]);
  for (int i = 0; i < 3; ++i) Comma(out, v->sigma_enu[i]);
}

std::optional<GnssVelocity> ParseGnssVelocity(const CsvRow& row) {
  const std::size_t c0 = kGnssVelocityColumn;
  int empty = 0;
  for (std::size_t c = c0; c < c0 + 6; ++c) empty += row.Text(c).empty() ? 1 : 0;
  if (empty == 6) return std::nullopt;
  GnssVelocity v;
  for (int i = 0; i < 3; ++i) {
    if (row.Text(c0 + i).empty() || row.Text(c0 + 3 + i).empty()) {
      row.Fail(row.Text(c0 + i).empty() ? c0 + i : c0 + 3 + i,
               "missing value (the six velocity cells are all numbers or all empty)");
    }
    v.v_enu[i] = row.Double(c0 + i);
    v.sigma_enu[i] = row.Double(c0 + 3 + i);
    if (!(v.sigma_enu[i] > 0.0)) row.Fail(c0 + 3 + i, "must be > 0");
  }
  return v;
}

}  // namespace

LogCsvLayout LogCsvLayoutOf(LogStreamType type, const std::vector<std::string>& header,
                            std::string_view file) {
  LogCsvLayout layout{type, false};
  const std::size_t own = LogCsvColumns(type).size();
  if (header.size() == own) return layout;
  layout.gnss_velocity = type == LogStreamType::kGnss;
  const std::vector<std::string> full = layout.Columns();
  for (std::size_t i = own; i < header.size(); ++i) {
    if (i >= full.size() || header[i] != full[i]) {
      throw InputError(std::string(file) + ":1: unexpected column '" + header[i] +
                       "' at position " + std::to_string(i + 1) +
                       (type == LogStreamType::kGnss
                            ? " (a gnss file may add exactly: ve, vn, vu, sigma_ve, sigma_vn, "
                              "sigma_vu [m s^-1])"
                            : ""));
    }
  }
  if (header.size() < full.size()) {
    throw InputError(std::string(file) + ":1: missing column '" + full[header.size()] +
                     "' (expected at position " + std::to_string(header.size() + 1) + ")");
  }
  return layout;
}

StampColumns StampColumnsOf(LogStreamType type) {
  return type == LogStreamType::kImu ? StampColumns{0, 7} : StampColumns{0, 1};
}

void AppendLogCsvRow(std::string& out, const Measurement& m, const LogCsvLayout& layout) {
  std::visit(
      [&out, &layout](const auto& x) {
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
          assert(layout.gnss_velocity || !x.velocity);
          if (layout.gnss_velocity) AppendGnssVelocity(out, x.velocity);
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

void CheckColumnCount(const LogCsvLayout& layout, const CsvRow& row) {
  const std::size_t expected = LogCsvColumns(layout.type).size() +
                               (layout.gnss_velocity ? GnssVelocityCsvColumns().size() : 0);
  if (row.size() > expected) {
    row.Fail(expected,
             "unexpected extra value (the file has " + std::to_string(expected) + " columns)");
  }
  if (row.size() < expected) row.Fail(row.size(), "missing value");
}

Measurement ParseLogCsvRow(const LogCsvLayout& layout, const std::string& id, const CsvRow& row) {
  CheckColumnCount(layout, row);
  const MeasurementHeader header = HeaderFrom(id, row, StampColumnsOf(layout.type));
  switch (layout.type) {
    case LogStreamType::kImu: {
      ImuSample s{header};
      for (int i = 0; i < 3; ++i) s.gyro[i] = row.Double(1 + i);
      for (int i = 0; i < 3; ++i) s.accel[i] = row.Double(4 + i);
      return s;
    }
    case LogStreamType::kGnss: {
      GnssFix f;
      f.header = header;
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
      if (layout.gnss_velocity) f.velocity = ParseGnssVelocity(row);
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
