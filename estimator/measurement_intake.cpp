#include "estimator/measurement_intake.hpp"

#include <algorithm>

#include "estimator/measurement_checks.hpp"

namespace statebench::est {
namespace {

constexpr TimeNs kMaxFutureNs = 2 * kNsPerSecond;  // stamp ahead of the newest IMU sample
// A measurement is taken before it arrives: a stamp later than the newest arrival stamp seen
// (plus a clock tolerance) is bogus. A bogus IMU stamp would otherwise make every later sample
// look like it goes backwards.
constexpr TimeNs kArrivalToleranceNs = 100 * kNsPerMillisecond;
constexpr std::size_t kStampsKeptPerSensor = 64;  // for repeated-stamp detection

// The value checks of each measurement kind (measurement_checks.hpp); none for kinds without.
struct ValueCheck {
  std::optional<RejectReason> operator()(const ImuSample& m) const { return CheckImuSample(m); }
  std::optional<RejectReason> operator()(const GnssFix& m) const { return CheckGnssFix(m); }
  std::optional<RejectReason> operator()(const DualAntennaHeading& m) const {
    return CheckDualAntennaHeading(m);
  }
  std::optional<RejectReason> operator()(const VehicleSpeed& m) const {
    return CheckVehicleSpeed(m);
  }
  std::optional<RejectReason> operator()(const SteeringAngle& m) const {
    return CheckSteeringAngle(m);
  }
  std::optional<RejectReason> operator()(const LidarScan& m) const { return CheckLidarScan(m); }
  std::optional<RejectReason> operator()(const BodyVelocity& m) const {
    return CheckBodyVelocity(m);
  }
  template <typename M>
  std::optional<RejectReason> operator()(const M&) const {
    return std::nullopt;
  }
};

}  // namespace

// Only when the stream carries arrival stamps (a reader that has none leaves them 0).
bool MeasurementIntake::AfterArrival(const MeasurementHeader& h) const {
  return newest_arrival_ns_ > 0 && h.stamp_ns > newest_arrival_ns_ + kArrivalToleranceNs;
}

std::optional<RejectReason> MeasurementIntake::CheckStamp(const MeasurementHeader& h,
                                                          TimeNs newest_imu_ns) {
  if (AfterArrival(h)) return RejectReason::kStampInFuture;
  if (newest_imu_ns != INT64_MIN && h.stamp_ns > newest_imu_ns + kMaxFutureNs) {
    return RejectReason::kStampInFuture;
  }
  std::set<TimeNs>& seen = seen_stamps_[h.sensor_id];
  if (!seen.insert(h.stamp_ns).second) return RejectReason::kStampBackwards;  // repeated
  if (seen.size() > kStampsKeptPerSensor) seen.erase(seen.begin());
  return std::nullopt;
}

Admission MeasurementIntake::AdmitImu(const ImuSample& s, FrontEndContext& ctx) {
  const std::string& id = s.header.sensor_id;
  std::optional<RejectReason> why;
  if (id != setup_.imu_id) {
    why = RejectReason::kUnknownSensor;
  } else if (!(why = CheckImuSample(s)) && !(why = CheckImuLimits(s, imu_limits_))) {
    if (s.header.stamp_ns <= ctx.newest_imu_ns) {
      why = RejectReason::kStampBackwards;
    } else if (AfterArrival(s.header)) {
      why = RejectReason::kStampInFuture;
    }
  }
  if (why) {
    ctx.Reject(id, s.header.stamp_ns, *why);
    return Admission::kRejected;
  }
  ctx.Accept(id, s.header.stamp_ns);
  ctx.newest_imu_ns = s.header.stamp_ns;
  reorder_.Push(s);
  return Admission::kImu;
}

Admission MeasurementIntake::Admit(const Measurement& m, Claim claim, FrontEndContext& ctx) {
  const MeasurementHeader& h = HeaderOf(m);
  ++ctx.Counters(h.sensor_id).received;
  if (h.arrival_ns > 0) newest_arrival_ns_ = std::max(newest_arrival_ns_, h.arrival_ns);
  if (const auto* s = std::get_if<ImuSample>(&m)) return AdmitImu(*s, ctx);
  std::optional<RejectReason> why;
  if (claim == Claim::kUnknownSensor) {
    why = RejectReason::kUnknownSensor;
  } else if (claim == Claim::kOtherKind) {
    why = setup_.Find(h.sensor_id) != nullptr ? RejectReason::kUnsupportedSensor
                                              : RejectReason::kUnknownSensor;
  } else if (!(why = std::visit(ValueCheck{}, m))) {
    why = CheckStamp(h, ctx.newest_imu_ns);
  }
  if (why) {
    ctx.Reject(h.sensor_id, h.stamp_ns, *why);
    return Admission::kRejected;
  }
  // Later than the reorder latency: no order guarantee, processed at once.
  if (h.stamp_ns <= reorder_.watermark_ns()) return Admission::kLate;
  reorder_.Push(m);
  return Admission::kQueued;
}

std::vector<Measurement> MeasurementIntake::Release(TimeNs newest_imu_ns) {
  return reorder_.Release(newest_imu_ns - latency_ns_);
}

}  // namespace statebench::est
