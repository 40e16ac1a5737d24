#include "estimator/ekf_single_track.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <variant>

#include "core/error.hpp"
#include "estimator/ekf_filter_impl.hpp"
#include "estimator/ekf_input_check.hpp"
#include "estimator/estimate_status.hpp"
#include "estimator/ekf_output_mapping.hpp"
#include "estimator/measurement_checks.hpp"
#include "estimator/measurement_gate.hpp"

namespace statebench::est {
namespace {

using namespace ekf;  // NOLINT: the state layout (kX, kPsi, ...) and the sensor roles

}  // namespace

EkfSingleTrackEstimator::Impl::Impl(const EstimatorSensorSetup& s, const EkfOptions& o)
    : setup(s), options(o) {
  std::string why;
  if (!options.IsValid(&why)) throw InputError(why);
  R_body_imu = setup.T_body_imu.rotation().toRotationMatrix();
  p_body_imu = setup.T_body_imu.translation();
  for (const EstimatorSensor& sensor : setup.sensors) {
    SensorInfo info;
    info.p_body_sensor = sensor.T_body_sensor.translation();
    info.R_body_sensor = sensor.T_body_sensor.rotation().toRotationMatrix();
    info.T_imu_sensor = sensor.T_imu_sensor;
    switch (sensor.kind) {
      case SensorKind::kImu:
        info.role = sensor.id == setup.imu_id ? Role::kImu : Role::kUnsupported;
        break;
      case SensorKind::kGnss:
        info.role = Role::kGnss;
        if (const GnssAntenna* antenna = setup.FindAntenna(sensor.id)) {
          info.p_body_sensor =
              setup.T_body_imu.rotation() * antenna->p_imu_antenna + setup.T_body_imu.translation();
          info.covariance_scale = antenna->covariance_scale;
          info.min_sigma_m = antenna->min_sigma_m;
        }
        if (course_antenna.empty()) course_antenna = sensor.id;
        break;
      case SensorKind::kSpeedEncoder:
        info.role = Role::kSpeed;
        has_speed_input = true;
        break;
      case SensorKind::kSteeringEncoder:
        info.role = Role::kSteering;
        has_steering = true;
        break;
      case SensorKind::kBodyVelocity:
        info.role = Role::kBodyVelocity;
        has_speed_input = true;
        break;
      default:
        info.role = Role::kUnsupported;
    }
    sensors[sensor.id] = info;
  }
  for (const DualAntennaPair& pair : setup.dual_antennas) {
    if (pair.heading_id.empty()) continue;
    SensorInfo info;
    info.role = Role::kHeading;
    const Vec3 baseline_body = setup.T_body_imu.rotation() * (pair.p_imu_aux - pair.p_imu_main);
    info.yaw_offset_rad = std::atan2(baseline_body.y(), baseline_body.x());
    sensors[pair.heading_id] = info;
  }
  if (course_antenna.empty()) ResetLocalStart();  // no GNSS: a local frame
  model.emplace(options, p_body_imu, has_steering);
  diag.warnings = EkfInputWarnings(setup, options.vehicle);
}

void EkfSingleTrackEstimator::Impl::Apply(const std::string& id, const SensorInfo& info,
                                          const Measurement& m) {
  if (const auto* fix = std::get_if<GnssFix>(&m)) {
    if (!frame)
      frame.emplace(GeodeticPoint{fix->latitude_deg, fix->longitude_deg, fix->altitude_m});
    // A fix without a useful height updates the horizontal state only (its vertical variance
    // then carries no information: the altitude filter's gain is ~0).
    GnssFix used = *fix;
    const bool horizontal_only =
        FixUse(AdjustedCovariance(fix->covariance_enu, info), options.gnss_max_sigma_m,
               options.gnss_max_vertical_sigma_m) == GnssFixUse::kHorizontalOnly;
    if (horizontal_only) used.covariance_enu = WithoutVertical(fix->covariance_enu);
    std::string why;
    const auto enu = GnssFixToEnu(used, *frame, &why);
    if (!enu) {
      Reject(id, fix->header.stamp_ns, RejectReason::kAbsurdValue);
      return;
    }
    const Mat3 cov = AdjustedCovariance(enu->covariance, info);
    if (FixUse(cov, options.gnss_max_sigma_m, std::numeric_limits<double>::infinity()) ==
        GnssFixUse::kDiscarded) {
      Reject(id, fix->header.stamp_ns, RejectReason::kCovarianceThreshold);
      return;
    }
    if (horizontal_only) ++diag.sensors[id].events["horizontal_only"];
    if (!initialized) {
      TryInitialize(id, info, *enu);
      Accept(id, HeaderOf(m).stamp_ns);
      return;
    }
    UpdateGnss(id, info, *enu);
    if (enu->velocity) {
      doppler.Add(enu->header.stamp_ns, enu->velocity->v_enu.head<2>(),
                  enu->velocity->sigma_enu.head<2>());
      if (initialized) UpdateGnssVelocity(id, info, *enu);  // not after StartOver
    }
  } else if (const auto* speed = std::get_if<VehicleSpeed>(&m)) {
    encoder_speed = speed->speed_mps;
    if (!initialized) {
      if (local_start) FeedLocalStart(id, info, m);
      Accept(id, HeaderOf(m).stamp_ns);
      return;
    }
    UpdateSpeed(id, info, *speed);
  } else if (const auto* velocity = std::get_if<BodyVelocity>(&m)) {
    if (!initialized) {
      // Before a local start the initialiser takes it; with GNSS the course starts the filter.
      if (local_start) return FeedLocalStart(id, info, m);
      return Reject(id, velocity->header.stamp_ns, RejectReason::kNotInitialized);
    }
    UpdateBodyVelocity(id, info, *velocity);
  } else if (const auto* heading = std::get_if<DualAntennaHeading>(&m)) {
    if (!initialized) {
      Reject(id, heading->header.stamp_ns, RejectReason::kNotInitialized);
      return;
    }
    if (heading->yaw_sigma_rad > options.heading_max_sigma_rad) {
      Reject(id, heading->header.stamp_ns, RejectReason::kCovarianceThreshold);
      return;
    }
    UpdateHeading(id, info, *heading);
  } else if (const auto* angle = std::get_if<SteeringAngle>(&m)) {
    steering = angle->angle_rad;
    Accept(id, HeaderOf(m).stamp_ns);
  }
}

void EkfSingleTrackEstimator::Impl::ReleasePending(TimeNs up_to_ns) {
  std::size_t n = 0;
  while (n < pending.size() && pending[n].stamp_ns <= up_to_ns) {
    const Pending& p = pending[n];
    if (initialized) Propagate(p.stamp_ns);
    Apply(p.sensor_id, sensors[p.sensor_id], p.measurement);
    ++n;
  }
  pending.erase(pending.begin(), pending.begin() + static_cast<std::ptrdiff_t>(n));
}

void EkfSingleTrackEstimator::Impl::AddImu(const std::string& id, const ImuSample& sample) {
  if (last_imu_ns && sample.header.stamp_ns <= *last_imu_ns) {
    Reject(id, sample.header.stamp_ns, RejectReason::kStampBackwards);
    return;
  }
  if (auto reason = CheckImuSample(sample); reason || (reason = CheckImuLimits(
                                                          sample, options.imu_limits))) {
    Reject(id, sample.header.stamp_ns, *reason);
    return;
  }
  Accept(id, sample.header.stamp_ns);
  // A pause of the IMU stream the model cannot bridge: start over from the next fixes.
  if (initialized && last_imu_ns &&
      sample.header.stamp_ns - *last_imu_ns > FromSeconds(options.imu_limits.max_gap_s)) {
    StartOver(id, sample.header.stamp_ns, "imu_gap");
  }
  const Vec3 gyro_body = R_body_imu * sample.gyro;
  const Vec3 accel_body = R_body_imu * sample.accel;
  accel_x = accel_body.x();
  gyro_z = gyro_body.z();
  course_start.AddForwardAccel(sample.header.stamp_ns, accel_x);
  ReleasePending(sample.header.stamp_ns);
  last_imu_ns = sample.header.stamp_ns;
  if (!initialized && local_start) TryStartLocal(sample, gyro_body.z());
  if (!initialized) return;
  still_imu.Push(sample);
  if (odometry_zero_since_ns && sample.header.stamp_ns > *odometry_zero_since_ns) {
    standstill_imu.push_back(sample);
    if (standstill_imu.size() > kMaxStandstillSamples) {  // the odometry stopped reading
      odometry_zero_since_ns.reset();
      standstill_imu.clear();
    }
  }
  Propagate(sample.header.stamp_ns);
  UpdateGyro(gyro_body.z());
  UpdateZeroVelocity(sample.header.stamp_ns);
  PushHistory();
}

std::optional<RejectReason> EkfSingleTrackEstimator::Impl::CheckOther(const Measurement& m) const {
  if (const auto* fix = std::get_if<GnssFix>(&m)) return CheckGnssFix(*fix);
  if (const auto* heading = std::get_if<DualAntennaHeading>(&m)) {
    return CheckDualAntennaHeading(*heading);
  }
  if (const auto* speed = std::get_if<VehicleSpeed>(&m)) return CheckVehicleSpeed(*speed);
  if (const auto* angle = std::get_if<SteeringAngle>(&m)) return CheckSteeringAngle(*angle);
  if (const auto* velocity = std::get_if<BodyVelocity>(&m)) return CheckBodyVelocity(*velocity);
  return std::nullopt;
}

bool EkfSingleTrackEstimator::Impl::TypeFits(Role role, const Measurement& m) {
  switch (role) {
    case Role::kImu:
      return std::holds_alternative<ImuSample>(m);
    case Role::kGnss:
      return std::holds_alternative<GnssFix>(m);
    case Role::kSpeed:
      return std::holds_alternative<VehicleSpeed>(m);
    case Role::kSteering:
      return std::holds_alternative<SteeringAngle>(m);
    case Role::kHeading:
      return std::holds_alternative<DualAntennaHeading>(m);
    case Role::kBodyVelocity:
      return std::holds_alternative<BodyVelocity>(m);
    case Role::kUnsupported:
      return true;
  }
  return false;
}

void EkfSingleTrackEstimator::Impl::Add(const Measurement& m) {
  const MeasurementHeader& header = HeaderOf(m);
  const std::string& id = header.sensor_id;
  ++diag.sensors[id].received;
  const auto it = sensors.find(id);
  if (it == sensors.end() || !TypeFits(it->second.role, m)) {
    Reject(id, header.stamp_ns, RejectReason::kUnknownSensor);
    return;
  }
  const SensorInfo& info = it->second;
  if (info.role == Role::kUnsupported) {
    Reject(id, header.stamp_ns, RejectReason::kUnsupportedSensor);
    return;
  }
  if (header.stamp_ns > header.arrival_ns) {
    Reject(id, header.stamp_ns, RejectReason::kStampInFuture);
    return;
  }
  newest_arrival_ns = std::max(newest_arrival_ns, header.arrival_ns);
  if (info.role == Role::kImu) {
    AddImu(id, std::get<ImuSample>(m));
    return;
  }
  if (const auto reason = CheckOther(m)) {
    Reject(id, header.stamp_ns, *reason);
    return;
  }
  if (const auto last = last_stamp.find(id);
      last != last_stamp.end() && header.stamp_ns <= last->second) {
    Reject(id, header.stamp_ns, RejectReason::kStampBackwards);
    return;
  }
  if (initialized && header.stamp_ns < t_ns - FromSeconds(options.max_delay_s)) {
    Reject(id, header.stamp_ns, RejectReason::kTooOld);
    return;
  }
  last_stamp[id] = header.stamp_ns;
  if (last_imu_ns && header.stamp_ns <= *last_imu_ns) {
    Apply(id, info, m);
    return;
  }
  Pending p{header.stamp_ns, id, m};
  const auto pos = std::upper_bound(pending.begin(), pending.end(), p.stamp_ns,
                                    [](TimeNs t, const Pending& q) { return t < q.stamp_ns; });
  pending.insert(pos, std::move(p));
}

std::optional<StateEstimate> EkfSingleTrackEstimator::Impl::StateAt(TimeNs t_out_ns) const {
  if (!initialized || history.empty() || !last_imu_ns || t_out_ns > *last_imu_ns) {
    return std::nullopt;
  }
  if (t_out_ns < history.front().t_ns) return std::nullopt;
  // Newest snapshot at or before t.
  auto it = std::upper_bound(history.begin(), history.end(), t_out_ns,
                             [](TimeNs t, const Snapshot& s) { return t < s.t_ns; });
  --it;
  const LocalEnuFrame* enu = local_start ? &local_frame : (frame ? &*frame : nullptr);
  StateEstimate out = EkfOutput(*it, t_out_ns, {*model, options, R_body_imu, p_body_imu, enu});
  if (!out.state.p_world.allFinite() || !out.covariance.allFinite()) return std::nullopt;
  out.status = StatusAt(diag, position_sensors, t_out_ns);
  return out;
}

EkfSingleTrackEstimator::EkfSingleTrackEstimator(const EstimatorSensorSetup& setup,
                                                 const EkfOptions& options)
    : impl_(std::make_unique<Impl>(setup, options)) {}

EkfSingleTrackEstimator::~EkfSingleTrackEstimator() = default;

void EkfSingleTrackEstimator::Add(const Measurement& measurement) { impl_->Add(measurement); }

std::optional<StateEstimate> EkfSingleTrackEstimator::StateAt(TimeNs t_ns) const {
  return impl_->StateAt(t_ns);
}

EstimatorDiagnostics EkfSingleTrackEstimator::diagnostics() const {
  EstimatorDiagnostics d = impl_->diag;
  if (!impl_->initialized) {
    d.waiting_for = impl_->local_start ? impl_->local_start->WaitingFor() : impl_->WaitingFor();
  }
  return d;
}

void EkfSingleTrackEstimator::SetVerdictObserver(VerdictObserver observer) {
  impl_->verdicts = std::move(observer);
}

std::optional<GeodeticPoint> EkfSingleTrackEstimator::origin() const {
  if (!impl_->frame) return std::nullopt;
  return impl_->frame->origin();
}

}  // namespace statebench::est
