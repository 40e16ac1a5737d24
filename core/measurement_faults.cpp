#include "core/measurement_faults.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <type_traits>
#include <utility>

#include "core/geodetic.hpp"

namespace statebench {
namespace {

using Kind = MeasurementFaultKind;

constexpr std::array<std::pair<Kind, std::string_view>, 9> kNames{{
    {Kind::kGap, "gap"},
    {Kind::kNonFinite, "non_finite"},
    {Kind::kDuplicate, "duplicate"},
    {Kind::kStampsBackwards, "stamps_backwards"},
    {Kind::kClockJump, "clock_jump"},
    {Kind::kGnssJump, "gnss_jump"},
    {Kind::kGnssOverconfident, "gnss_overconfident"},
    {Kind::kLidarGarbage, "lidar_garbage"},
    {Kind::kImuSaturation, "imu_saturation"},
}};

template <typename T>
std::size_t IndexOf() {
  return Measurement(std::in_place_type<T>).index();
}

// The numeric fields of a measurement other than a lidar scan, in a fixed order.
std::vector<double*> NumericFields(Measurement* m) {
  std::vector<double*> fields;
  const auto add = [&fields](auto& matrix) {
    for (Eigen::Index i = 0; i < matrix.size(); ++i) fields.push_back(matrix.data() + i);
  };
  std::visit(
      [&](auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, ImuSample>) {
          add(x.gyro);
          add(x.accel);
        } else if constexpr (std::is_same_v<T, GnssFix>) {
          fields.insert(fields.end(), {&x.latitude_deg, &x.longitude_deg, &x.altitude_m});
          add(x.covariance_enu);
        } else if constexpr (std::is_same_v<T, DualAntennaHeading>) {
          fields.insert(fields.end(),
                        {&x.yaw_rad, &x.pitch_rad, &x.yaw_sigma_rad, &x.pitch_sigma_rad});
        } else if constexpr (std::is_same_v<T, WheelSpeeds>) {
          for (double& w : x.omega_radps) fields.push_back(&w);
        } else if constexpr (std::is_same_v<T, VehicleSpeed>) {
          fields.push_back(&x.speed_mps);
        } else if constexpr (std::is_same_v<T, SteeringAngle>) {
          fields.push_back(&x.angle_rad);
        } else if constexpr (std::is_same_v<T, BodyVelocity>) {
          add(x.velocity);
          add(x.angular_velocity);
          add(x.covariance);
        }
      },
      *m);
  return fields;
}

// A private copy of a scan's points (scans share theirs between copies of the measurement).
std::vector<LidarPoint>& OwnPoints(LidarScan* scan) {
  auto points = scan->points ? std::make_shared<std::vector<LidarPoint>>(*scan->points)
                             : std::make_shared<std::vector<LidarPoint>>();
  scan->points = points;
  return *points;
}

void MoveFix(GnssFix* fix, const Vec3& offset_enu) {
  const LocalEnuFrame at_fix({fix->latitude_deg, fix->longitude_deg, fix->altitude_m});
  const GeodeticPoint moved = at_fix.ToGeodetic(offset_enu);
  fix->latitude_deg = moved.latitude_deg;
  fix->longitude_deg = moved.longitude_deg;
  fix->altitude_m = moved.altitude_m;
}

double Rail(double reading, double limit) { return reading < 0.0 ? -limit : limit; }

// Applies one fault to m (already known to be covered); false: m is dropped.
bool Alter(const MeasurementFault& f, std::uint64_t count, Measurement* m) {
  MeasurementHeader& h = std::visit([](auto& x) -> MeasurementHeader& { return x.header; }, *m);
  switch (f.kind) {
    case Kind::kGap:
      return false;
    case Kind::kNonFinite:
      CorruptNumericField(m, static_cast<std::size_t>(count), f.value);
      return true;
    case Kind::kDuplicate:
      return true;  // repeated by the caller
    case Kind::kStampsBackwards:
      h.stamp_ns -= FromSeconds(f.shift_s);
      h.arrival_ns -= FromSeconds(f.shift_s);
      return true;
    case Kind::kClockJump:
      // A clock behind the log's start would stamp the first samples before it: they are not
      // delivered (the log begins at 0).
      h.stamp_ns += FromSeconds(f.shift_s);
      return h.stamp_ns >= 0;
    case Kind::kGnssJump:
    case Kind::kGnssOverconfident: {
      auto& fix = std::get<GnssFix>(*m);
      if (std::isfinite(fix.latitude_deg) && std::isfinite(fix.longitude_deg) &&
          std::isfinite(fix.altitude_m) && std::abs(fix.latitude_deg) <= 90.0) {
        MoveFix(&fix, f.offset_m);
      }
      if (f.kind == Kind::kGnssOverconfident) {
        fix.covariance_enu = Mat3::Identity() * (f.sigma_m * f.sigma_m);
      }
      return true;
    }
    case Kind::kLidarGarbage: {
      for (LidarPoint& p : OwnPoints(&std::get<LidarScan>(*m))) {
        const double r = std::sqrt(double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z);
        const double scale = f.far_m > 0.0 && r > 0.0 ? f.far_m / r : 0.0;
        p.x = static_cast<float>(p.x * scale);
        p.y = static_cast<float>(p.y * scale);
        p.z = static_cast<float>(p.z * scale);
      }
      return true;
    }
    case Kind::kImuSaturation: {
      auto& imu = std::get<ImuSample>(*m);
      for (int i = 0; i < 3; ++i) {
        imu.accel[i] = Rail(imu.accel[i], f.accel_limit_mps2);
        imu.gyro[i] = Rail(imu.gyro[i], f.gyro_limit_radps);
      }
      return true;
    }
  }
  return true;
}

}  // namespace

std::string_view MeasurementFaultName(MeasurementFaultKind kind) {
  for (const auto& [k, name] : kNames) {
    if (k == kind) return name;
  }
  return "?";
}

bool ParseMeasurementFaultKind(std::string_view name, MeasurementFaultKind* kind) {
  for (const auto& [k, n] : kNames) {
    if (n == name) {
      *kind = k;
      return true;
    }
  }
  return false;
}

std::vector<std::size_t> MeasurementFaultTypes(MeasurementFaultKind kind) {
  switch (kind) {
    case Kind::kGnssJump:
    case Kind::kGnssOverconfident:
      return {IndexOf<GnssFix>()};
    case Kind::kLidarGarbage:
      return {IndexOf<LidarScan>()};
    case Kind::kImuSaturation:
      return {IndexOf<ImuSample>()};
    default:
      return {};
  }
}

bool MeasurementFault::Covers(const MeasurementHeader& header, std::size_t type_index) const {
  const double t = ToSeconds(header.stamp_ns);
  if (!(t >= start_s && t < end_s)) return false;
  const std::vector<std::size_t> types = MeasurementFaultTypes(kind);
  if (!types.empty() && std::find(types.begin(), types.end(), type_index) == types.end()) {
    return false;
  }
  return sensors.empty() ||
         std::find(sensors.begin(), sensors.end(), header.sensor_id) != sensors.end();
}

void CorruptNumericField(Measurement* m, std::size_t field, double value) {
  if (auto* scan = std::get_if<LidarScan>(m)) {
    std::vector<LidarPoint>& points = OwnPoints(scan);
    const auto v = static_cast<float>(value);
    for (std::size_t i = field % 10; i < points.size(); i += 10) {
      float* fields[5] = {&points[i].x, &points[i].y, &points[i].z, &points[i].intensity,
                          &points[i].t};
      *fields[field % 5] = v;
    }
    return;
  }
  const std::vector<double*> fields = NumericFields(m);
  if (!fields.empty()) *fields[field % fields.size()] = value;
}

MeasurementFaultInjector::MeasurementFaultInjector(std::vector<MeasurementFault> faults)
    : faults_(std::move(faults)), affected_(faults_.size(), 0) {}

void MeasurementFaultInjector::Apply(const Measurement& m, std::vector<Measurement>* out) {
  Measurement altered = m;
  int copies = 1;
  // Windows and sensors are those of the measurement as the sensor produced it.
  const MeasurementHeader original = HeaderOf(m);
  for (std::size_t i = 0; i < faults_.size(); ++i) {
    const MeasurementFault& f = faults_[i];
    if (!f.Covers(original, m.index())) continue;
    if (!Alter(f, affected_[i]++, &altered)) return;
    if (f.kind == Kind::kDuplicate) copies = 2;
  }
  for (int k = 0; k < copies; ++k) out->push_back(altered);
}

}  // namespace statebench
