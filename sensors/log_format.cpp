#include "sensors/log_format.hpp"

#include <array>
#include <variant>

namespace statebench::sensors {
namespace {

static_assert(std::variant_size_v<Measurement> == 8, "one log stream type per measurement type");

constexpr std::array<std::string_view, 8> kTypeNames = {
    "imu",          "gnss",          "dual_antenna_heading",
    "wheel_speeds", "vehicle_speed", "steering_angle",
    "lidar",        "body_velocity"};
constexpr std::array<std::string_view, 8> kFolders = {
    "imu", "gnss", "heading", "wheels", "speed", "steering", "lidar", "body_velocity"};
constexpr std::array<std::string_view, 4> kStatusNames = {"none", "single", "rtk_float",
                                                          "rtk_fixed"};

std::vector<std::string> WithStamps(std::vector<std::string> values) {
  values.insert(values.begin(), {"timestamp [ns]", "arrival [ns]"});
  return values;
}

std::vector<std::vector<std::string>> MakeColumns() {
  std::vector<std::vector<std::string>> c(8);
  // EuRoC / ASL imu0/data.csv columns, then the arrival.
  c[0] = {"timestamp [ns]",    "w_RS_S_x [rad s^-1]", "w_RS_S_y [rad s^-1]", "w_RS_S_z [rad s^-1]",
          "a_RS_S_x [m s^-2]", "a_RS_S_y [m s^-2]",   "a_RS_S_z [m s^-2]",   "arrival [ns]"};
  c[1] = WithStamps({"latitude [deg]", "longitude [deg]", "altitude [m]", "cov_ee [m^2]",
                     "cov_en [m^2]", "cov_eu [m^2]", "cov_ne [m^2]", "cov_nn [m^2]", "cov_nu [m^2]",
                     "cov_ue [m^2]", "cov_un [m^2]", "cov_uu [m^2]", "status"});
  c[2] = WithStamps({"yaw [rad]", "pitch [rad]", "yaw_sigma [rad]", "pitch_sigma [rad]"});
  c[3] = WithStamps(
      {"omega_fl [rad s^-1]", "omega_fr [rad s^-1]", "omega_rl [rad s^-1]", "omega_rr [rad s^-1]"});
  c[4] = WithStamps({"speed [m s^-1]"});
  c[5] = WithStamps({"angle [rad]"});
  c[6] = WithStamps({"points", "file"});
  std::vector<std::string> body = {"v_x [m s^-1]",   "v_y [m s^-1]",   "v_z [m s^-1]",
                                   "w_x [rad s^-1]", "w_y [rad s^-1]", "w_z [rad s^-1]"};
  for (int r = 0; r < 6; ++r) {
    for (int k = 0; k < 6; ++k) body.push_back("cov_" + std::to_string(r) + std::to_string(k));
  }
  c[7] = WithStamps(std::move(body));
  return c;
}

}  // namespace

std::string_view LogStreamTypeName(LogStreamType type) {
  return kTypeNames[static_cast<int>(type)];
}

std::optional<LogStreamType> ParseLogStreamType(std::string_view name) {
  for (std::size_t i = 0; i < kTypeNames.size(); ++i) {
    if (kTypeNames[i] == name) return static_cast<LogStreamType>(i);
  }
  return std::nullopt;
}

std::string_view LogStreamFolder(LogStreamType type) { return kFolders[static_cast<int>(type)]; }

LogStreamType StreamTypeOf(const Measurement& m) { return static_cast<LogStreamType>(m.index()); }

const std::vector<std::string>& LogCsvColumns(LogStreamType type) {
  static const std::vector<std::vector<std::string>> columns = MakeColumns();
  return columns[static_cast<int>(type)];
}

const std::vector<std::string>& GnssVelocityCsvColumns() {
  static const std::vector<std::string> columns = {"ve [m s^-1]",       "vn [m s^-1]",
                                                   "vu [m s^-1]",       "sigma_ve [m s^-1]",
                                                   "sigma_vn [m s^-1]", "sigma_vu [m s^-1]"};
  return columns;
}

std::vector<std::string> LogCsvLayout::Columns() const {
  std::vector<std::string> columns = LogCsvColumns(type);
  if (gnss_velocity) {
    const auto& v = GnssVelocityCsvColumns();
    columns.insert(columns.end(), v.begin(), v.end());
  }
  return columns;
}

std::string_view GnssStatusName(GnssFixStatus status) {
  return kStatusNames[static_cast<int>(status)];
}

std::optional<GnssFixStatus> ParseGnssStatus(std::string_view name) {
  for (std::size_t i = 0; i < kStatusNames.size(); ++i) {
    if (kStatusNames[i] == name) return static_cast<GnssFixStatus>(i);
  }
  return std::nullopt;
}

}  // namespace statebench::sensors
