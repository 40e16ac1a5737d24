#include "estimator/factor_graph_estimator.hpp"

#include <algorithm>
#include <chrono>
#include <deque>
#include <map>
#include <set>
#include <span>

#include "core/error.hpp"
#include "estimator/gnss_enu.hpp"
#include "estimator/gnss_stamp_group.hpp"
#include "estimator/imu_propagation.hpp"
#include "estimator/imu_rate_output.hpp"
#include "estimator/measurement_checks.hpp"
#include "estimator/measurement_gate.hpp"
#include "estimator/reorder_buffer.hpp"
#include "estimator/sliding_window_smoother.hpp"
#include "estimator/state_initializer.hpp"

namespace statebench::est {
namespace {

constexpr TimeNs kMaxFutureNs = 2 * kNsPerSecond;  // stamp ahead of the newest IMU sample
// A measurement is taken before it arrives: a stamp later than the newest arrival stamp seen
// (plus a clock tolerance) is bogus. A bogus IMU stamp would otherwise make every later sample
// look like it goes backwards.
constexpr TimeNs kArrivalToleranceNs = 100 * kNsPerMillisecond;
constexpr std::size_t kStampsKeptPerSensor = 64;  // for repeated-stamp detection

SlidingWindowOptions SmootherOptions(const EstimatorSensorSetup& setup,
                                     const FactorGraphOptions& o) {
  SlidingWindowOptions s;
  s.window_s = o.window_s;
  s.imu_samples_per_state = o.imu_samples_per_state;
  s.imu_noise = setup.imu_noise.value_or(o.imu_noise);
  s.gnss_kernel = o.gnss.kernel;
  s.heading_kernel = o.heading.kernel;
  s.max_iterations = o.max_iterations;
  s.num_threads = o.num_threads;
  return s;
}

// A measurement in the smoother, kept until it leaves the window to check its final residual
// against the robust kernel's scale.
struct Accepted {
  TimeNs stamp_ns = 0;
  std::string sensor_id;
  bool is_heading = false;
  GnssPositionEnu fix;
  Vec3 p_imu_antenna = Vec3::Zero();
  DualAntennaHeading heading;
  Vec3 baseline_imu = Vec3::Zero();
};

// Last time a measurement of a kind passed the gate, for the gate's reset.
struct GateState {
  TimeNs last_accepted_ns = INT64_MIN;
  bool rejected_since = false;
};

}  // namespace

struct FactorGraphEstimator::Impl {
  Impl(const EstimatorSensorSetup& s, const FactorGraphOptions& o)
      : setup(s),
        options(o),
        noise(s.imu_noise.value_or(o.imu_noise)),
        smoother(SmootherOptions(s, o)),
        initializer(o.initialization, noise,
                    setup.T_body_imu.rotation().conjugate() * Vec3::UnitX()),
        output(noise),
        latency_ns(FromSeconds(o.ReorderLatency(s))) {
    if (o.origin) frame.emplace(*o.origin);
  }

  EstimatorSensorSetup setup;
  FactorGraphOptions options;
  ImuNoise noise;
  SlidingWindowSmoother smoother;
  StateInitializer initializer;
  ImuRateOutput output;
  ReorderBuffer reorder;
  TimeNs latency_ns;
  std::optional<LocalEnuFrame> frame;
  EstimatorDiagnostics diag;

  TimeNs newest_imu_ns = INT64_MIN;
  TimeNs newest_arrival_ns = INT64_MIN;  // arrival stamps given (> 0) so far
  std::map<std::string, std::set<TimeNs>> seen_stamps;
  bool initialized = false;
  TimeNs lagged_ns = INT64_MIN;  // newest IMU stamp released to the smoother
  TimeNs next_solve_ns = 0;
  std::deque<Accepted> accepted;   // in the smoother, oldest first
  std::vector<NavState> smoothed;  // left the window, not taken yet
  GateState gnss_gate, heading_gate;

  SensorCounters& Counters(const std::string& id) { return diag.sensors[id]; }
  void Reject(const std::string& id, RejectReason reason) { ++Counters(id).rejected[reason]; }

  // ---- 1. Arrival -------------------------------------------------------------------------

  void AddImu(const ImuSample& s) {
    const std::string& id = s.header.sensor_id;
    if (id != setup.imu_id) return Reject(id, RejectReason::kUnknownSensor);
    if (const auto why = CheckImuSample(s)) return Reject(id, *why);
    if (s.header.stamp_ns <= newest_imu_ns) return Reject(id, RejectReason::kStampBackwards);
    if (AfterArrival(s.header)) return Reject(id, RejectReason::kStampInFuture);
    ++Counters(id).accepted;
    newest_imu_ns = s.header.stamp_ns;
    output.AddImu(s);
    reorder.Push(s);
    ReleaseUpTo(s.header.stamp_ns - latency_ns);
  }

  // Only when the stream carries arrival stamps (a reader that has none leaves them 0).
  bool AfterArrival(const MeasurementHeader& h) const {
    return newest_arrival_ns > 0 && h.stamp_ns > newest_arrival_ns + kArrivalToleranceNs;
  }

  // Common arrival checks of GNSS fixes and headings; true if the measurement may go on.
  bool CheckStamp(const MeasurementHeader& h) {
    if (AfterArrival(h)) {
      Reject(h.sensor_id, RejectReason::kStampInFuture);
      return false;
    }
    if (newest_imu_ns != INT64_MIN && h.stamp_ns > newest_imu_ns + kMaxFutureNs) {
      Reject(h.sensor_id, RejectReason::kStampInFuture);
      return false;
    }
    std::set<TimeNs>& seen = seen_stamps[h.sensor_id];
    if (!seen.insert(h.stamp_ns).second) {
      Reject(h.sensor_id, RejectReason::kStampBackwards);  // a repeated stamp
      return false;
    }
    if (seen.size() > kStampsKeptPerSensor) seen.erase(seen.begin());
    return true;
  }

  template <typename M>
  void AddOther(const M& m, bool known, std::optional<RejectReason> (*check)(const M&)) {
    const std::string& id = m.header.sensor_id;
    if (!known) return Reject(id, RejectReason::kUnknownSensor);
    if (const auto why = check(m)) return Reject(id, *why);
    if (!CheckStamp(m.header)) return;
    if (m.header.stamp_ns <= reorder.watermark_ns()) {
      ProcessLate(Measurement(m));  // later than the reorder latency: no order guarantee
    } else {
      reorder.Push(m);
    }
  }

  void Add(const Measurement& m) {
    const MeasurementHeader& h = HeaderOf(m);
    ++Counters(h.sensor_id).received;
    if (h.arrival_ns > 0) newest_arrival_ns = std::max(newest_arrival_ns, h.arrival_ns);
    if (const auto* s = std::get_if<ImuSample>(&m)) return AddImu(*s);
    if (const auto* f = std::get_if<GnssFix>(&m)) {
      return AddOther(*f, setup.FindAntenna(h.sensor_id) != nullptr, &CheckGnssFix);
    }
    if (const auto* d = std::get_if<DualAntennaHeading>(&m)) {
      return AddOther(*d, setup.FindHeading(h.sensor_id) != nullptr, &CheckDualAntennaHeading);
    }
    Reject(h.sensor_id, setup.Find(h.sensor_id) != nullptr ? RejectReason::kUnsupportedSensor
                                                           : RejectReason::kUnknownSensor);
  }

  // ---- 2. Release in stamp order ----------------------------------------------------------

  void ReleaseUpTo(TimeNs watermark_ns) {
    std::vector<Measurement> released = reorder.Release(watermark_ns);
    std::vector<Measurement> group;  // non-IMU measurements of one stamp
    const auto flush = [&] {
      if (!group.empty()) ProcessGroup(group);
      group.clear();
    };
    for (Measurement& m : released) {
      if (const auto* s = std::get_if<ImuSample>(&m)) {
        flush();
        ProcessImu(*s);
      } else {
        if (!group.empty() && HeaderOf(group.front()).stamp_ns != HeaderOf(m).stamp_ns) flush();
        group.push_back(std::move(m));
      }
    }
    flush();
    if (initialized && lagged_ns >= next_solve_ns) Solve();
  }

  void ProcessLate(const Measurement& m) {
    if (!initialized) return Reject(HeaderOf(m).sensor_id, RejectReason::kNotInitialized);
    ProcessGroup({m});
  }

  // ---- 3. Initialisation -------------------------------------------------------------------

  void ProcessImu(const ImuSample& s) {
    smoother.AddImu(s);
    lagged_ns = s.header.stamp_ns;
    if (initialized) return;
    initializer.AddImu(s);
    const std::optional<InitialState> init = initializer.TryInitialize();
    if (!init) return;
    const NavState& x = init->state;
    if (!x.q_world_imu.coeffs().allFinite() || !x.p_world.allFinite() || !x.v_world.allFinite() ||
        !init->covariance.allFinite()) {
      return;  // a degenerate geometry (e.g. fixes on one spot): wait for more data
    }
    try {
      smoother.Initialize(init->state, init->covariance);
    } catch (const InputError&) {
      return;  // covariance not positive definite: same
    }
    initialized = true;
    diag.initialized = true;
    diag.initialized_at_ns = init->state.t_ns;
    diag.initialization = init->method;
    output.SetAnchor(PropagatedState{init->state, init->covariance});
    next_solve_ns = init->state.t_ns + FromSeconds(options.solve_interval_s);
    gnss_gate.last_accepted_ns = heading_gate.last_accepted_ns = init->state.t_ns;
  }

  // ---- 4. GNSS and headings ----------------------------------------------------------------

  // The fix in ENU with the antenna's covariance overrides; nullopt (counted) if the covariance
  // threshold discards it. The first fix that passes sets the origin if the options give none.
  std::optional<GnssPositionEnu> ToEnu(const GnssFix& fix) {
    GnssFix adjusted = fix;
    adjusted.covariance_enu =
        AntennaCovariance(*setup.FindAntenna(fix.header.sensor_id), fix.covariance_enu);
    if (LargestSigma(adjusted.covariance_enu) > options.gnss.max_sigma) {
      Reject(fix.header.sensor_id, RejectReason::kCovarianceThreshold);
      return std::nullopt;
    }
    if (!frame) frame.emplace(GeodeticPoint{fix.latitude_deg, fix.longitude_deg, fix.altitude_m});
    std::optional<GnssPositionEnu> enu = GnssFixToEnu(adjusted, *frame);
    if (!enu) Reject(fix.header.sensor_id, RejectReason::kInvalidCovariance);
    return enu;
  }

  void ProcessGroup(const std::vector<Measurement>& group) {
    std::map<std::string, GnssPositionEnu> fixes;        // by antenna id
    std::map<std::string, DualAntennaHeading> headings;  // by heading id
    for (const Measurement& m : group) {
      if (const auto* f = std::get_if<GnssFix>(&m)) {
        if (auto enu = ToEnu(*f)) fixes[f->header.sensor_id] = *enu;
      } else if (const auto* h = std::get_if<DualAntennaHeading>(&m)) {
        if (h->yaw_sigma_rad > options.heading.max_sigma) {
          Reject(h->header.sensor_id, RejectReason::kCovarianceThreshold);
        } else {
          headings[h->header.sensor_id] = *h;
        }
      }
    }
    const StampGroup inputs = GroupStamp(fixes, headings, setup);
    for (const std::string& id : inputs.merged) ++Counters(id).accepted;  // via the heading
    for (const PositionInput& p : inputs.positions) AddPosition(p);
    for (const HeadingInput& h : inputs.headings) AddHeading(h);
  }

  bool PassesGate(const MeasurementGateOptions& gate, GateState& state, TimeNs t_ns,
                  double mahalanobis_squared) {
    if (mahalanobis_squared <= gate.gate_chi2) return true;
    const bool reset = state.rejected_since && state.last_accepted_ns != INT64_MIN &&
                       t_ns - state.last_accepted_ns > FromSeconds(gate.gate_reset_s);
    state.rejected_since = !reset;
    return reset;
  }

  void AddPosition(const PositionInput& in) {
    const GnssPositionEnu& fix = in.fix;
    const std::string& id = fix.header.sensor_id;
    const Vec3& lever = in.p_imu_antenna;
    if (!initialized) {
      ++Counters(id).accepted;
      return initializer.AddPosition(fix, lever);
    }
    if (const auto predicted = PredictAt(fix.header.stamp_ns)) {
      const double d2 = GnssMahalanobisSquared(*predicted, lever, fix.p_enu, fix.covariance);
      if (!PassesGate(options.gnss, gnss_gate, fix.header.stamp_ns, d2)) {
        return Reject(id, RejectReason::kMahalanobisGate);
      }
    }
    if (smoother.AddGnss(fix, lever) == AddResult::kTooOld) {
      return Reject(id, RejectReason::kTooOld);
    }
    gnss_gate = {std::max(gnss_gate.last_accepted_ns, fix.header.stamp_ns), false};
    ++Counters(id).accepted;
    Accepted a;
    a.stamp_ns = fix.header.stamp_ns;
    a.sensor_id = id;
    a.fix = fix;
    a.p_imu_antenna = lever;
    accepted.push_back(a);
  }

  void AddHeading(const HeadingInput& in) {
    const std::string& id = in.counter_id;
    const TimeNs t = in.heading.header.stamp_ns;
    // A heading paired from fixes on one spot has no direction (NaN).
    if (const auto why = CheckDualAntennaHeading(in.heading)) return Reject(id, *why);
    if (!initialized) {
      ++Counters(id).accepted;
      return initializer.AddHeading(in.heading, in.baseline_imu);
    }
    if (const auto predicted = PredictAt(t)) {
      const double d2 = HeadingMahalanobisSquared(*predicted, in.baseline_imu, in.heading);
      if (!PassesGate(options.heading, heading_gate, t, d2)) {
        return Reject(id, RejectReason::kMahalanobisGate);
      }
    }
    const Vec3 main = Vec3::Zero();  // the factor only uses the baseline direction
    try {
      if (smoother.AddDualAntenna(in.heading, main, in.baseline_imu) == AddResult::kTooOld) {
        return Reject(id, RejectReason::kTooOld);
      }
    } catch (const InputError&) {
      return Reject(id, RejectReason::kAbsurdValue);  // e.g. a vertical baseline
    }
    heading_gate = {std::max(heading_gate.last_accepted_ns, t), false};
    ++Counters(id).accepted;
    Accepted a;
    a.stamp_ns = t;
    a.sensor_id = id;
    a.is_heading = true;
    a.heading = in.heading;
    a.baseline_imu = in.baseline_imu;
    accepted.push_back(a);
  }

  // ---- 5. Solve ------------------------------------------------------------------------------

  void Solve() {
    const auto start = std::chrono::steady_clock::now();
    const SmootherSolveSummary summary = smoother.Solve();
    std::vector<NavState> left = smoother.TakeMarginalizedStates();
    const NavState newest = smoother.NewestState();
    const Mat15 covariance = smoother.NewestCovariance();
    const auto stop = std::chrono::steady_clock::now();

    UpdateDiagnostics u;
    u.t_ns = newest.t_ns;
    u.solve_time_s = std::chrono::duration<double>(stop - start).count();
    u.iterations = summary.iterations;
    u.usable = summary.usable;
    u.num_states = summary.num_states;
    u.num_marginalized = summary.num_marginalized;
    u.factors = {{"prior", 1},
                 {"imu", summary.num_imu_factors},
                 {"bias", summary.num_imu_factors},
                 {"gnss", summary.num_gnss_factors},
                 {"heading", summary.num_heading_factors}};
    diag.updates.push_back(u);

    CountDownweighted(left);
    smoothed.insert(smoothed.end(), left.begin(), left.end());
    if (newest.q_world_imu.coeffs().allFinite() && newest.p_world.allFinite() &&
        newest.v_world.allFinite() && covariance.allFinite()) {
      output.SetAnchor(PropagatedState{newest, covariance});
    }
    const TimeNs interval = FromSeconds(options.solve_interval_s);
    while (next_solve_ns <= lagged_ns) next_solve_ns += interval;
    TrimHistory();
  }

  // Measurements anchored at states that left the window are final: compare their whitened
  // residual at the final estimate with the robust kernel's scale.
  void CountDownweighted(const std::vector<NavState>& left) {
    if (left.empty()) return;
    const TimeNs t_window = smoother.WindowStates().front().t_ns;
    while (!accepted.empty() && accepted.front().stamp_ns < t_window) {
      const Accepted& a = accepted.front();
      auto it = std::upper_bound(left.begin(), left.end(), a.stamp_ns,
                                 [](TimeNs t, const NavState& s) { return t < s.t_ns; });
      if (it != left.begin()) {
        const PropagatedState at{output.Carry(*std::prev(it), a.stamp_ns), Mat15::Zero()};
        const double d2 = a.is_heading ? HeadingMahalanobisSquared(at, a.baseline_imu, a.heading)
                                       : GnssMahalanobisSquared(at, a.p_imu_antenna, a.fix.p_enu,
                                                                a.fix.covariance);
        const RobustKernel& k = a.is_heading ? options.heading.kernel : options.gnss.kernel;
        if (k.type != RobustKernelType::kNone && d2 > k.scale * k.scale) {
          ++Counters(a.sensor_id).downweighted;
        }
      }
      accepted.pop_front();
    }
  }

  void TrimHistory() {
    TimeNs keep = smoother.WindowStates().front().t_ns;
    if (!accepted.empty()) keep = std::min(keep, accepted.front().stamp_ns);
    output.Forget(keep);
  }

  // ---- 6. Output ---------------------------------------------------------------------------

  std::optional<PropagatedState> PredictAt(TimeNs t_ns) const {
    if (const auto p = output.AfterAnchor(t_ns)) return p;
    if (!output.has_anchor() || t_ns > newest_imu_ns) return std::nullopt;
    const std::vector<NavState> window = smoother.WindowStates();
    return output.InWindow(t_ns, window);
  }
};

FactorGraphEstimator::FactorGraphEstimator(const EstimatorSensorSetup& setup,
                                           const FactorGraphOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw InputError(why);
  impl_ = std::make_unique<Impl>(setup, options);
}

FactorGraphEstimator::~FactorGraphEstimator() = default;

void FactorGraphEstimator::Add(const Measurement& measurement) { impl_->Add(measurement); }

std::optional<StateEstimate> FactorGraphEstimator::StateAt(TimeNs t_ns) const {
  const std::optional<PropagatedState> p = impl_->PredictAt(t_ns);
  if (!p || !impl_->frame) return std::nullopt;
  StateEstimate out;
  out.state = p->state;
  out.covariance = p->covariance;
  const GeodeticPoint g = impl_->frame->ToGeodetic(out.state.p_world);
  out.latitude_deg = g.latitude_deg;
  out.longitude_deg = g.longitude_deg;
  out.altitude_m = g.altitude_m;
  const NavState& s = out.state;
  if (!s.q_world_imu.coeffs().allFinite() || !s.p_world.allFinite() || !s.v_world.allFinite() ||
      !s.gyro_bias.allFinite() || !s.accel_bias.allFinite() || !out.covariance.allFinite() ||
      !std::isfinite(out.latitude_deg) || !std::isfinite(out.longitude_deg)) {
    return std::nullopt;
  }
  return out;
}

EstimatorDiagnostics FactorGraphEstimator::diagnostics() const { return impl_->diag; }

std::vector<NavState> FactorGraphEstimator::TakeSmoothedStates() {
  std::vector<NavState> out;
  out.swap(impl_->smoothed);
  return out;
}

std::optional<GeodeticPoint> FactorGraphEstimator::origin() const {
  if (!impl_->frame) return std::nullopt;
  return impl_->frame->origin();
}

}  // namespace statebench::est
