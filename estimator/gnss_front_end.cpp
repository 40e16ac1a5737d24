#include "estimator/gnss_front_end.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "estimator/dual_antenna_factor.hpp"
#include "estimator/gnss_calibration_covariance.hpp"
#include "estimator/gnss_enu.hpp"
#include "estimator/measurement_checks.hpp"
#include "estimator/measurement_gate.hpp"

namespace statebench::est {
namespace {

constexpr TimeNs kRecentImuNs = 2 * kNsPerSecond;  // longer than any reorder latency

}  // namespace

GnssFrontEnd::GnssFrontEnd(const EstimatorSensorSetup& setup, const FactorGraphOptions& options,
                           FrontEndContext& ctx)
    : setup_(setup), options_(options), ctx_(ctx) {
  if (options.origin) frame_.emplace(*options.origin);
}

Claim GnssFrontEnd::Claims(const Measurement& m) const {
  const std::string& id = HeaderOf(m).sensor_id;
  if (std::holds_alternative<GnssFix>(m)) {
    return setup_.FindAntenna(id) != nullptr ? Claim::kTaken : Claim::kUnknownSensor;
  }
  if (std::holds_alternative<DualAntennaHeading>(m)) {
    return setup_.FindHeading(id) != nullptr ? Claim::kTaken : Claim::kUnknownSensor;
  }
  return Claim::kOtherKind;
}

// The fix in ENU with the antenna's covariance overrides; nullopt (counted) if the covariance
// threshold discards it, its height unused (counted) when its vertical sigma is too large. The
// first fix that passes sets the origin if the options give none.
std::optional<GnssPositionEnu> GnssFrontEnd::ToEnu(const GnssFix& fix) {
  GnssFix adjusted = fix;
  adjusted.covariance_enu =
      AntennaCovariance(*setup_.FindAntenna(fix.header.sensor_id), fix.covariance_enu);
  switch (
      FixUse(adjusted.covariance_enu, options_.gnss.max_sigma, options_.gnss.max_vertical_sigma)) {
    case GnssFixUse::kDiscarded:
      ctx_.Reject(fix.header.sensor_id, fix.header.stamp_ns, RejectReason::kCovarianceThreshold);
      return std::nullopt;
    case GnssFixUse::kHorizontalOnly:
      adjusted.covariance_enu = WithoutVertical(adjusted.covariance_enu);
      ctx_.Count(fix.header.sensor_id, "horizontal_only");
      break;
    case GnssFixUse::kFull:
      break;
  }
  if (!frame_) frame_.emplace(GeodeticPoint{fix.latitude_deg, fix.longitude_deg, fix.altitude_m});
  std::optional<GnssPositionEnu> enu = GnssFixToEnu(adjusted, *frame_);
  if (!enu)
    ctx_.Reject(fix.header.sensor_id, fix.header.stamp_ns, RejectReason::kInvalidCovariance);
  return enu;
}

void GnssFrontEnd::Process(const Measurement& m) {
  stamp_ns_ = HeaderOf(m).stamp_ns;
  if (const auto* f = std::get_if<GnssFix>(&m)) {
    if (auto enu = ToEnu(*f)) fixes_[f->header.sensor_id] = *enu;
  } else if (const auto* h = std::get_if<DualAntennaHeading>(&m)) {
    if (h->yaw_sigma_rad > options_.heading.max_sigma) {
      ctx_.Reject(h->header.sensor_id, h->header.stamp_ns, RejectReason::kCovarianceThreshold);
    } else {
      headings_[h->header.sensor_id] = *h;
    }
  }
}

void GnssFrontEnd::EndOfStamp() {
  if (fixes_.empty() && headings_.empty()) return;
  const StampGroup inputs = GroupStamp(fixes_, headings_, setup_);
  fixes_.clear();
  headings_.clear();
  for (const std::string& id : inputs.merged) ctx_.Accept(id, stamp_ns_);  // via the heading
  for (const PositionInput& p : inputs.positions) AddPosition(p);
  for (const HeadingInput& h : inputs.headings) AddHeading(h);
}

void GnssFrontEnd::OnImu(const ImuSample& sample) {
  recent_imu_.push_back(sample);
  while (recent_imu_.front().header.stamp_ns < sample.header.stamp_ns - kRecentImuNs) {
    recent_imu_.pop_front();
  }
}

Vec3 GnssFrontEnd::RecentGyro(TimeNs t_ns) const {
  const ImuSample* best = nullptr;
  for (const ImuSample& s : recent_imu_) {
    if (best == nullptr ||
        std::abs(s.header.stamp_ns - t_ns) < std::abs(best->header.stamp_ns - t_ns)) {
      best = &s;
    }
  }
  return best != nullptr ? best->gyro : Vec3::Zero();
}

void GnssFrontEnd::OnInitialized(const InitialState& init) {
  const TimeNs t_ns = init.state.t_ns;
  alignment_.Clear();
  gnss_gate_.last_accepted_ns = heading_gate_.last_accepted_ns = t_ns;
  velocity_gate_.last_accepted_ns = t_ns;
  AddStartAsFix(init);
}

void GnssFrontEnd::OnRestart() {
  accepted_.clear();
  refused_.Clear();
  alignment_.Clear();
  gnss_gate_ = heading_gate_ = velocity_gate_ = GateState{};
}

bool GnssFrontEnd::PassesGate(const MeasurementGateOptions& gate, GateState& state, TimeNs t_ns,
                              double mahalanobis_squared) {
  if (mahalanobis_squared <= gate.gate_chi2) return true;
  const bool reset = state.rejected_since && state.last_accepted_ns != INT64_MIN &&
                     t_ns - state.last_accepted_ns > FromSeconds(gate.gate_reset_s);
  state.rejected_since = !reset;
  return reset;
}

void GnssFrontEnd::AddPosition(const PositionInput& in) {
  GnssPositionEnu fix = in.fix;
  const std::string& id = fix.header.sensor_id;
  const Vec3& lever = in.p_imu_antenna;
  if (!ctx_.initialized) {
    ctx_.Accept(id, fix.header.stamp_ns);
    return ctx_.initializer.AddPosition(fix, lever);
  }
  if (ctx_.local_frame) return AlignLocalFrame(fix, lever);
  if (fix.velocity) AddVelocity(in);
  InnovationScale* scale = nullptr;
  if (options_.gnss.adapt_covariance) {
    scale = &covariance_scales_.try_emplace(id, 3, options_.gnss.gate_chi2).first->second;
    fix.covariance *= scale->scale();
  }
  const double offset_s = TimeOffsetEstimate(id);
  if (const auto predicted = ctx_.PredictAt(fix.header.stamp_ns - FromSeconds(offset_s))) {
    fix.covariance += PositionCalibrationCovariance(
        options_.gnss_calibration, predicted->state.q_world_imu, predicted->state.v_world, lever);
    const GnssPositionEnu gated = LessErrorEstimate(fix);
    const double d2 = GnssMahalanobisSquared(*predicted, lever, gated.p_enu, gated.covariance);
    if (scale != nullptr && scale->Add(d2)) {
      ctx_.Count(id, "covariance_scale_changed");
      ctx_.Counters(id).covariance_scale = scale->scale();
    }
    const bool outside = d2 > options_.gnss.gate_chi2;
    if (outside) refused_.Refused(fix);
    if (!PassesGate(options_.gnss, gnss_gate_, fix.header.stamp_ns, d2)) {
      return ctx_.Reject(id, fix.header.stamp_ns, RejectReason::kMahalanobisGate);
    }
    // The gate has refused every fix for gate_reset_s: if they agree with each other, the
    // estimate is lost; the estimator starts over from the sensors (this fix included).
    if (outside && refused_.Agrees()) {
      ctx_.lost = true;
      ctx_.diag.Lost(fix.header.stamp_ns, "lost");
      ctx_.Count(id, "lost");
      ctx_.Reject(id, fix.header.stamp_ns, RejectReason::kMahalanobisGate);
      return;
    }
  }
  refused_.Clear();
  if (ctx_.smoother.AddGnss(fix, lever, TimeOffsetOf(id), ErrorStateOf(id)) == AddResult::kTooOld) {
    return ctx_.Reject(id, fix.header.stamp_ns, RejectReason::kTooOld);
  }
  gnss_gate_ = {std::max(gnss_gate_.last_accepted_ns, fix.header.stamp_ns), false};
  ctx_.Accept(id, fix.header.stamp_ns);
  Accepted a;
  a.stamp_ns = fix.header.stamp_ns;
  a.sensor_id = id;
  a.fix = fix;
  a.p_imu_antenna = lever;
  accepted_.push_back(a);
}

void GnssFrontEnd::AlignLocalFrame(const GnssPositionEnu& fix, const Vec3& p_imu_antenna) {
  const std::string& id = fix.header.sensor_id;
  const TimeNs t = fix.header.stamp_ns;
  const std::optional<NavState> predicted = ctx_.PredictMeanAt(t);
  if (!predicted) return ctx_.Reject(id, t, RejectReason::kTooOld);
  const NavState& x = *predicted;
  alignment_.Add(t, x.p_world + x.q_world_imu * p_imu_antenna, fix.p_enu, fix.covariance);
  ctx_.Accept(id, t);
  ctx_.Count(id, "enu_alignment");
  const std::optional<EnuAlignment::Result> r = alignment_.Solve();
  // As a GNSS course start: the yaw to course_yaw_sigma_rad and fixes over course_min_distance_m
  // (a short track's own error, not in the fit, would dominate its yaw).
  const InitializationOptions& o = options_.initialization;
  if (!r || r->yaw_sigma_rad > o.course_yaw_sigma_rad ||
      2.0 * r->span_m < o.course_min_distance_m) {
    return;
  }
  ctx_.enu_switch = r;
  alignment_.Clear();
  gnss_gate_ = heading_gate_ = velocity_gate_ = GateState{t, false};
}

void GnssFrontEnd::AddVelocity(const PositionInput& in) {
  const GnssPositionEnu& fix = in.fix;
  const GnssVelocity& velocity = *fix.velocity;
  const std::string& id = fix.header.sensor_id;
  const TimeNs t = fix.header.stamp_ns;
  if (velocity.sigma_enu.maxCoeff() > options_.gnss_velocity.max_sigma) {
    return ctx_.Count(id, "velocity_too_noisy");
  }
  doppler_.Add(t, velocity.v_enu.head<2>(), velocity.sigma_enu.head<2>());
  if (const auto predicted = ctx_.PredictAt(t)) {
    const double d2 =
        GnssVelocityMahalanobisSquared(*predicted, in.p_imu_antenna, RecentGyro(t), velocity);
    if (!PassesGate(options_.gnss_velocity, velocity_gate_, t, d2)) {
      return ctx_.Count(id, "velocity_gated");
    }
  }
  BodyVelocityMeasurement m;
  m.frame = BodyVelocityMeasurement::Frame::kWorld;
  m.v_frame = velocity.v_enu;
  m.sqrt_information = velocity.sigma_enu.cwiseInverse().asDiagonal();
  m.p_imu_point = in.p_imu_antenna;
  if (ctx_.smoother.AddBodyVelocity(t, m, options_.gnss_velocity.kernel) == AddResult::kTooOld) {
    return;
  }
  velocity_gate_ = {std::max(velocity_gate_.last_accepted_ns, t), false};
  ctx_.Count(id, "velocity_factors");
}

void GnssFrontEnd::AddHeading(const HeadingInput& in) {
  const std::string& id = in.counter_id;
  const TimeNs t = in.heading.header.stamp_ns;
  // A heading paired from fixes on one spot has no direction (NaN).
  if (const auto why = CheckDualAntennaHeading(in.heading)) return ctx_.Reject(id, t, *why);
  if (!ctx_.initialized) {
    ctx_.Accept(id, t);
    return ctx_.initializer.AddHeading(in.heading, in.baseline_imu);
  }
  if (ctx_.local_frame) return ctx_.Reject(id, t, RejectReason::kNotInitialized);
  DualAntennaHeading heading = in.heading;
  const std::optional<std::array<int, 2>> baseline = BaselineOf(id, in.baseline_imu);
  Vec3 baseline_imu = in.baseline_imu;  // as the gate sees it
  if (baseline) {
    baseline_imu = DualAntennaFactor::TurnedBaseline(in.baseline_imu,
                                                     ctx_.smoother.Global((*baseline)[0]).value,
                                                     ctx_.smoother.Global((*baseline)[1]).value);
  } else {
    const HeadingCalibrationVariance calibration =
        HeadingCalibration(options_.gnss_calibration, in.baseline_imu);
    heading.yaw_sigma_rad =
        std::sqrt(heading.yaw_sigma_rad * heading.yaw_sigma_rad + calibration.yaw_rad2);
    if (std::isfinite(heading.pitch_sigma_rad) && heading.pitch_sigma_rad > 0.0) {  // else no pitch
      heading.pitch_sigma_rad =
          std::sqrt(heading.pitch_sigma_rad * heading.pitch_sigma_rad + calibration.pitch_rad2);
    }
  }
  if (const auto predicted = ctx_.PredictAt(t)) {
    const double d2 = HeadingMahalanobisSquared(*predicted, baseline_imu, heading);
    if (!PassesGate(options_.heading, heading_gate_, t, d2)) {
      return ctx_.Reject(id, t, RejectReason::kMahalanobisGate);
    }
  }
  const Vec3 main = Vec3::Zero();  // the factor only uses the baseline direction
  try {
    if (ctx_.smoother.AddDualAntenna(heading, main, in.baseline_imu, baseline) ==
        AddResult::kTooOld) {
      return ctx_.Reject(id, t, RejectReason::kTooOld);
    }
  } catch (const InputError&) {
    return ctx_.Reject(id, t, RejectReason::kAbsurdValue);  // e.g. a vertical baseline
  }
  heading_gate_ = {std::max(heading_gate_.last_accepted_ns, t), false};
  ctx_.Accept(id, t);
  heading_pitch_seen_ |= std::isfinite(heading.pitch_sigma_rad) && heading.pitch_sigma_rad > 0.0;
  Accepted a;
  a.stamp_ns = t;
  a.sensor_id = id;
  a.is_heading = true;
  a.heading = heading;
  a.baseline_imu = baseline_imu;
  accepted_.push_back(a);
}

std::optional<int> GnssFrontEnd::TimeOffsetOf(const std::string& antenna_id) {
  if (!options_.gnss.estimate_time_offset) return std::nullopt;
  return ctx_.Global(antenna_id, kTimeOffsetGlobal, options_.gnss.time_offset_prior_sigma_s,
                     options_.gnss.time_offset_max_s);
}

std::optional<std::array<int, 2>> GnssFrontEnd::BaselineOf(const std::string& heading_id,
                                                           const Vec3& baseline_imu) {
  if (!options_.gnss_calibration.estimate_heading_baseline) return std::nullopt;
  const HeadingCalibrationVariance prior =
      HeadingCalibration(options_.gnss_calibration, baseline_imu);
  if (!(prior.yaw_rad2 > 0.0) || !(prior.pitch_rad2 > 0.0)) return std::nullopt;
  const double sigma[2] = {std::sqrt(prior.yaw_rad2), std::sqrt(prior.pitch_rad2)};
  std::array<int, 2> indices{};
  for (int k = 0; k < 2; ++k) {
    indices[k] = ctx_.Global(heading_id, kBaselineGlobals[k], sigma[k], 5.0 * sigma[k]);
  }
  return indices;
}

std::optional<std::array<int, 3>> GnssFrontEnd::ErrorStateOf(const std::string& antenna_id) {
  const GnssAntenna& antenna = *setup_.FindAntenna(antenna_id);
  if (!options_.gnss.EstimatesCorrelatedErrorOf(antenna)) return std::nullopt;
  const SlowError e = SlowErrorOf(antenna);
  std::array<int, 3> indices{};
  for (int k = 0; k < 3; ++k) {
    indices[k] = ctx_.Global(antenna_id, kErrorGlobals[k], e.sigma[k], 5.0 * e.sigma[k], e.tau_s);
  }
  return indices;
}

GnssPositionEnu GnssFrontEnd::LessErrorEstimate(const GnssPositionEnu& fix) const {
  GnssPositionEnu out = fix;
  for (int k = 0; k < 3; ++k) {
    const std::optional<int> index = ctx_.FindGlobal(fix.header.sensor_id, kErrorGlobals[k]);
    if (!index) return fix;  // not estimated (all three are created together)
    const SlidingWindowSmoother::GlobalEstimate e = ctx_.smoother.Global(*index);
    out.p_enu(k) -= e.value;
    out.covariance(k, k) += e.sigma * e.sigma;
  }
  return out;
}

double GnssFrontEnd::TimeOffsetEstimate(const std::string& antenna_id) const {
  const std::optional<int> index = ctx_.FindGlobal(antenna_id, kTimeOffsetGlobal);
  return index ? ctx_.smoother.Global(*index).value : 0.0;
}

// Measurements anchored at states that left the window are final: compare their whitened
// residual at the final estimate with the robust kernel's scale.
void GnssFrontEnd::OnMarginalized(std::span<const NavState> left) {
  if (left.empty()) return;
  const TimeNs t_window = ctx_.smoother.WindowStates().front().t_ns;
  while (!accepted_.empty() && accepted_.front().stamp_ns < t_window) {
    const Accepted& a = accepted_.front();
    // A fix is the antenna at its stamp minus the receiver's time offset (0 unless estimated).
    const TimeNs t_taken =
        a.stamp_ns - FromSeconds(a.is_heading ? 0.0 : TimeOffsetEstimate(a.sensor_id));
    auto it = std::upper_bound(left.begin(), left.end(), t_taken,
                               [](TimeNs t, const NavState& s) { return t < s.t_ns; });
    if (it != left.begin()) {
      const PropagatedState at{ctx_.output.Carry(*std::prev(it), t_taken), Mat15::Zero()};
      const double d2 =
          a.is_heading ? HeadingMahalanobisSquared(at, a.baseline_imu, a.heading)
                       : GnssMahalanobisSquared(at, a.p_imu_antenna, LessErrorEstimate(a.fix).p_enu,
                                                a.fix.covariance);
      const RobustKernel& k = a.is_heading ? options_.heading.kernel : options_.gnss.kernel;
      if (k.type != RobustKernelType::kNone && d2 > k.scale * k.scale) {
        ++ctx_.Counters(a.sensor_id).downweighted;
      }
    }
    accepted_.pop_front();
  }
}

TimeNs GnssFrontEnd::OldestStampNeeded() const {
  return accepted_.empty() ? INT64_MAX : accepted_.front().stamp_ns;
}

}  // namespace statebench::est
