// Faults injected into a measurement stream: what a broken sensor, driver or clock delivers
// instead of what it measured. The simulator applies them between the sensors and the estimators
// (a scenario's `faults.injected` and `faults.sensor_outages`, docs/scenarios.md), the estimator
// tests apply them to synthetic streams; the estimators must reject, count and recover.
//
//   MeasurementFaultInjector injector({fault, ...});
//   std::vector<Measurement> out;
//   injector.Apply(measurement, &out);   // 0, 1 or 2 measurements (dropped, altered, repeated)
//
// A fault acts on the measurements of its sensors whose (true) stamp is in [start_s, end_s).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"

namespace statebench {

enum class MeasurementFaultKind {
  kGap,                // nothing delivered (a sensor outage)
  kNonFinite,          // one numeric field per measurement set to `value` (NaN, inf, 1e300, ...)
  kDuplicate,          // every measurement delivered twice
  kStampsBackwards,    // stamp and arrival moved back by shift_s
  kClockJump,          // stamp moved by shift_s (the sensor's clock jumped), arrival unchanged;
                       // a stamp moved before 0 (the log's start) is not delivered
  kGnssJump,           // GNSS fixes moved by offset_m (ENU), covariance as reported
  kGnssOverconfident,  // GNSS fixes moved by offset_m while reporting sigma_m
  kLidarGarbage,       // every lidar point at the origin (far_m 0) or at far_m along its ray
  kImuSaturation,      // every IMU axis at its rail: +-accel_limit_mps2, +-gyro_limit_radps
};

// Scenario spelling of each kind ("gap", "non_finite", ...) and back; false when unknown.
std::string_view MeasurementFaultName(MeasurementFaultKind kind);
bool ParseMeasurementFaultKind(std::string_view name, MeasurementFaultKind* kind);
// The measurement types a kind acts on, by Measurement variant index; empty: every type.
std::vector<std::size_t> MeasurementFaultTypes(MeasurementFaultKind kind);

struct MeasurementFault {
  MeasurementFaultKind kind = MeasurementFaultKind::kGap;
  std::vector<std::string> sensors;  // empty: every sensor of a type the kind acts on
  double start_s = 0.0;
  double end_s = 0.0;  // +inf: to the end

  double value = 0.0;               // kNonFinite: the value written (NaN, +-inf, 1e300, ...)
  double shift_s = 1.0;             // kStampsBackwards (back), kClockJump (signed)
  Vec3 offset_m = Vec3(100, 0, 0);  // kGnssJump, kGnssOverconfident (ENU at the fix)
  double sigma_m = 0.01;            // kGnssOverconfident: reported per-axis sigma
  double far_m = 0.0;               // kLidarGarbage: 0 = at the origin, else that far
  double accel_limit_mps2 = 16.0 * 9.80665;
  double gyro_limit_radps = 2000.0 * 3.14159265358979323846 / 180.0;

  bool Covers(const MeasurementHeader& header, std::size_t type_index) const;
};

// Writes `value` into the field-th numeric field of m (counted modulo the number of fields of its
// type: IMU 6, fix 3 + 9 covariance, heading 4, wheels 4, speed 1, steering 1, body velocity
// 6 + 36, lidar: every point's x, y, z, intensity or t, each tenth point). Used by kNonFinite and
// by the fuzz targets.
void CorruptNumericField(Measurement* m, std::size_t field, double value);

class MeasurementFaultInjector {
 public:
  MeasurementFaultInjector() = default;
  explicit MeasurementFaultInjector(std::vector<MeasurementFault> faults);

  bool empty() const { return faults_.empty(); }
  // Appends to `out` what the stream delivers instead of m; faults apply in their list order.
  void Apply(const Measurement& m, std::vector<Measurement>* out);

  const std::vector<MeasurementFault>& faults() const { return faults_; }
  // Measurements each fault acted on so far (same order as faults()).
  const std::vector<std::uint64_t>& affected() const { return affected_; }

 private:
  std::vector<MeasurementFault> faults_;
  std::vector<std::uint64_t> affected_;
};

}  // namespace statebench
