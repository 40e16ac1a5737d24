// The factor graph as named steps: intake (checks, reordering) -> release in stamp order ->
// initialisation -> front ends (GNSS, encoders, motion constraints, lidar) turn measurements into
// smoother factors -> solve at solve_interval_s -> IMU-rate output from the newest solved state.
#include "estimator/factor_graph_estimator.hpp"

#include <chrono>
#include <cstdio>

#include "core/error.hpp"
#include "estimator/batch_output.hpp"
#include "estimator/estimate_status.hpp"
#include "estimator/factor_plan.hpp"
#include "estimator/front_end_set.hpp"
#include "estimator/gnss_calibration_covariance.hpp"
#include "estimator/imu_triad_globals.hpp"
#include "estimator/measurement_intake.hpp"
#include "estimator/output_blend.hpp"
#include "estimator/solve_diagnostics.hpp"
#include "estimator/state_estimate.hpp"

namespace statebench::est {
namespace {

// Without GNSS: a local frame. With GNSS and body-frame odometry: a local frame until the GNSS
// can place it in ENU (without odometry, the IMU alone drifts too fast to align its track).
LocalStart LocalStartOf(const EstimatorSensorSetup& setup) {
  LocalStart local;
  for (const EstimatorSensor& s : setup.sensors) {
    local.has_odometry |=
        s.kind == SensorKind::kBodyVelocity || s.kind == SensorKind::kSpeedEncoder;
  }
  local.enu_later = !setup.PositionSensorIds().empty();
  local.enabled = !local.enu_later || local.has_odometry;
  return local;
}

}  // namespace

struct FactorGraphEstimator::Impl {
  Impl(const EstimatorSensorSetup& s, const FactorGraphOptions& o, LidarOdometryPool* lidar_pool)
      : setup(s),
        options(o),
        plan(PlanFactors(setup, o)),
        ctx(SmootherOptions(setup, o), o.initialization, s.imu_noise.value_or(o.imu_noise),
            setup.T_body_imu.rotation().conjugate() * Vec3::UnitX(), LocalStartOf(setup),
            o.imu_noise_estimation),
        intake(setup, FromSeconds(o.ReorderLatency(setup)), o.imu_limits),
        front_end_set(MakeFrontEnds(setup, plan, options, ctx, lidar_pool)) {
    for (const auto& f : front_end_set.all) front_ends.push_back(f.get());
  }

  EstimatorSensorSetup setup;  // the estimator's own copy: the plan and front ends point into it
  std::vector<std::string> position_sensors = setup.PositionSensorIds();
  FactorGraphOptions options;
  // Without an absolute-position sensor the estimate is in a local frame; its WGS84 position is
  // that frame placed at options.origin, or at latitude, longitude and height 0 (meaningless:
  // the status says `local`).
  LocalEnuFrame local_frame{options.origin.value_or(GeodeticPoint{0.0, 0.0, 0.0})};
  FactorPlan plan;
  FrontEndContext ctx;
  MeasurementIntake intake;
  FrontEndSet front_end_set;  // a new measurement kind is a new front end there
  std::vector<MeasurementFrontEnd*> front_ends;
  // What StateAt shows: the IMU-rate output with each solve's correction blended in (the front
  // ends' predictions, PredictAt, are not blended).
  OutputBlend blend{options.output_blend};

  Mat15 CalibrationConsider(const NavState& state) const {
    return OutputCalibrationConsider(setup, options, front_end_set.gnss->heading_pitch_seen(),
                                     state);
  }

  // The segments of the full-batch smoother (options.batch) or of the lagged output
  // (options.lagged_output), and whether the log has ended.
  BatchOutput batch{setup.imu_noise.value_or(options.imu_noise)};
  bool ended = false;

  TimeNs lagged_ns = INT64_MIN;                // newest IMU stamp released to the smoother
  std::optional<ImuSample> last_released_imu;  // the sample at lagged_ns
  TimeNs next_solve_ns = 0;
  bool keep_smoothed = false;
  std::vector<NavState> smoothed;  // left the window, not taken yet (when kept)

  // ---- 1. Intake: checks and reordering ------------------------------------------------------

  void Add(const Measurement& m) {
    const Claim claim = Route(m).second;
    const TimeNs previous_imu_ns = ctx.newest_imu_ns;
    const Admission admission = intake.Admit(m, claim, ctx);
    if (admission == Admission::kImu) {
      // A pause of the IMU stream no integration can bridge: start over from the sensors.
      if (ctx.initialized && previous_imu_ns != INT64_MIN &&
          ctx.newest_imu_ns - previous_imu_ns > FromSeconds(options.imu_limits.max_gap_s)) {
        ctx.diag.Lost(ctx.newest_imu_ns, "imu_gap");
        ctx.Count(HeaderOf(m).sensor_id, "imu_gap");
        for (const Measurement& old : intake.DropBefore(ctx.newest_imu_ns)) {
          ctx.Count(HeaderOf(old).sensor_id, "dropped_at_restart");
        }
        StartOver();
      }
      ctx.output.AddImu(std::get<ImuSample>(m));
      Release(intake.Release(ctx.newest_imu_ns));
    } else if (admission == Admission::kLate) {  // no order guarantee: at once
      if (!ctx.initialized)
        return ctx.Reject(HeaderOf(m).sensor_id, HeaderOf(m).stamp_ns,
                          RejectReason::kNotInitialized);
      ProcessStamp({m});
    }
  }

  // The front end that takes m, with the best claim any front end makes on it.
  std::pair<MeasurementFrontEnd*, Claim> Route(const Measurement& m) const {
    Claim best = Claim::kOtherKind;
    for (MeasurementFrontEnd* f : front_ends) {
      const Claim c = f->Claims(m);
      if (c == Claim::kTaken) return {f, c};
      if (c == Claim::kUnknownSensor) best = c;
    }
    return {nullptr, best};
  }

  // ---- 2. Release in stamp order -------------------------------------------------------------

  void Release(std::vector<Measurement> released) {
    std::vector<Measurement> stamp;  // non-IMU measurements of one stamp
    const auto flush = [&] {
      if (!stamp.empty()) ProcessStamp(stamp);
      stamp.clear();
    };
    for (Measurement& m : released) {
      if (const auto* s = std::get_if<ImuSample>(&m)) {
        flush();
        ProcessImu(*s);
      } else {
        if (!stamp.empty() && HeaderOf(stamp.front()).stamp_ns != HeaderOf(m).stamp_ns) flush();
        stamp.push_back(std::move(m));
      }
    }
    flush();
    for (MeasurementFrontEnd* f : front_ends) f->AfterRelease();
    if (ctx.initialized && lagged_ns >= next_solve_ns) Solve();
  }

  // Each measurement to its front end, pass 0 before pass 1 (e.g. steering before speed).
  void ProcessStamp(const std::vector<Measurement>& stamp) {
    for (int pass : {0, 1}) {
      for (const Measurement& m : stamp) {
        MeasurementFrontEnd* f = Route(m).first;
        if (f != nullptr && f->Pass(m) == pass) f->Process(m);
      }
    }
    for (MeasurementFrontEnd* f : front_ends) f->EndOfStamp();
    if (ctx.lost) {
      StartOver();
    } else if (ctx.enu_switch) {
      SwitchToEnu();
    }
  }

  // Lost (a front end said so): an empty window and initialiser, fed again from the next IMU
  // sample; no estimate until initialised again.
  void StartOver() {
    CloseBatchSegment();
    ctx.Restart();
    ctx.diag.local_frame = false;
    blend.Reset();
    for (MeasurementFrontEnd* f : front_ends) f->OnRestart();
  }

  void ProcessImu(const ImuSample& s) {
    ctx.smoother.AddImu(s);
    lagged_ns = s.header.stamp_ns;
    last_released_imu = s;
    for (MeasurementFrontEnd* f : front_ends) f->OnImu(s);
    if (!ctx.initialized) TryInitialize(s);
  }

  // ---- 3. Initialisation ---------------------------------------------------------------------

  void TryInitialize(const ImuSample& s) {
    ctx.initializer.AddImu(s);
    std::optional<InitialState> init = ctx.initializer.TryInitialize();
    if (!init) return;
    for (const MeasurementFrontEnd* f : front_ends) f->RefineInitialState(s, &*init);
    const NavState& x = init->state;
    if (!x.q_world_imu.coeffs().allFinite() || !x.p_world.allFinite() || !x.v_world.allFinite() ||
        !init->covariance.allFinite()) {
      return;  // a degenerate geometry (e.g. fixes on one spot): wait for more data
    }
    try {
      ctx.smoother.Initialize(init->state, init->SmootherPrior());
    } catch (const InputError&) {
      return;  // covariance not positive definite: same
    }
    ctx.initialized = true;
    AddImuTriadGlobals(options.imu_triad, setup.imu_id, &ctx);
    ctx.local_frame = init->local_frame && !position_sensors.empty();
    ctx.diag.local_frame = init->local_frame;
    ctx.diag.Initialized(x.t_ns, init->method);
    ctx.output.SetAnchor(PropagatedState{x, init->OutputCovariance()});
    blend.Start(x.t_ns);  // nothing was shown before
    next_solve_ns = x.t_ns + FromSeconds(options.solve_interval_s);
    for (MeasurementFrontEnd* f : front_ends) f->OnInitialized(*init);
  }

  // ---- 3b. From a local frame into ENU ------------------------------------------------------

  // The fixes placed the local frame in ENU (enu_alignment.hpp). The state at the newest
  // released IMU sample, moved into ENU with the alignment's uncertainty added, starts a new
  // window: its marginal covariance carries what the old window knew (biases, velocity, tilt,
  // their correlations); the IMU-rate output goes on from it through the buffered samples, with
  // no gap. Estimates before the switch are in the local frame (status `local`), after it in ENU;
  // the output's step at the switch is the change of frame (diagnostics: enu_switches).
  void SwitchToEnu() {
    const EnuAlignment::Result a = *ctx.enu_switch;
    ctx.enu_switch.reset();
    const std::optional<PropagatedState> now = ctx.output.AfterAnchor(lagged_ns);
    if (!now || !last_released_imu || last_released_imu->header.stamp_ns != lagged_ns) return;
    // The yaw prior at least what a GNSS course start takes: the fit does not model the local
    // track's own error.
    const PropagatedState enu = a.Apply(*now, options.initialization.course_yaw_sigma_rad);
    CloseBatchSegment();
    ctx.RestartSmoother();
    ctx.smoother.AddImu(*last_released_imu);
    try {
      ctx.smoother.Initialize(enu.state, enu.covariance);
    } catch (const InputError&) {  // not positive definite: start over from the sensors
      ctx.diag.Lost(lagged_ns, "enu_switch");
      return StartOver();
    }
    AddImuTriadGlobals(options.imu_triad, setup.imu_id, &ctx);
    ctx.output.SetAnchor(enu);
    blend.Start(lagged_ns);
    next_solve_ns = lagged_ns + FromSeconds(options.solve_interval_s);
    ctx.local_frame = false;
    ctx.diag.local_frame = false;
    ctx.diag.enu_switches.push_back({lagged_ns,
                                     a.fixes,
                                     a.span_m,
                                     a.yaw_rad,
                                     {a.translation.x(), a.translation.y(), a.translation.z()},
                                     a.yaw_sigma_rad,
                                     a.sigma_h_m,
                                     a.residual_sigma_h_m});
  }

  // ---- 3c. The full-batch smoother ----------------------------------------------------------

  // The smoother run that ends here (a restart, the switch into ENU, the end of the log) solved
  // as a whole (SlidingWindowSmoother::SolveBatch), into the batch output.
  // With lagged_output, the run's lagged states instead (SlidingWindowSmoother::LaggedStates).
  void CloseBatchSegment() {
    if (!ctx.smoother.initialized()) return;
    if (options.lagged_output) return batch.Add(ctx.smoother.LaggedStates(), ctx.local_frame);
    if (!options.batch) return;
    const auto start = std::chrono::steady_clock::now();
    SmootherBatch b = ctx.smoother.SolveBatch(options.batch_max_iterations);
    const auto stop = std::chrono::steady_clock::now();
    ctx.diag.batch_solves.push_back({b.states.front().t_ns, b.states.back().t_ns,
                                     static_cast<int>(b.states.size()), b.iterations,
                                     b.initial_cost, b.final_cost, b.usable,
                                     std::chrono::duration<double>(stop - start).count()});
    batch.Add(std::move(b), ctx.local_frame);
  }

  // Everything still held is released (in stamp order) and the window solved once more; with
  // the batch, the last segment is then solved as a whole.
  void EndOfLog() {
    if (ended) return;
    ended = true;
    Release(intake.ReleaseAll());
    if (ctx.initialized) Solve();
    CloseBatchSegment();
  }

  // The batch estimate at t_ns once the log has ended; nullopt before. The calibration share is
  // added as for the fixed-lag output; there is no correction to blend.
  std::optional<StateEstimate> BatchStateAt(TimeNs t_ns) const {
    if (!ended) return std::nullopt;
    const std::optional<BatchOutput::At> at = batch.StateAt(t_ns);
    if (!at) return std::nullopt;
    PropagatedState p = at->state;
    p.covariance += CalibrationConsider(p.state);
    return Present(p, at->local_frame, t_ns);
  }

  // p as the estimate at t_ns: in the local frame (no position sensor, or a state of a local
  // start) or in ENU once the GNSS front end has its frame (else nullopt), with its status.
  std::optional<StateEstimate> Present(const PropagatedState& p, bool local_state,
                                       TimeNs t_ns) const {
    const std::optional<LocalEnuFrame>& enu = front_end_set.gnss->frame();
    const bool local = position_sensors.empty() || local_state;
    const LocalEnuFrame* frame = local ? &local_frame : (enu ? &*enu : nullptr);
    if (frame == nullptr) return std::nullopt;
    std::optional<StateEstimate> out = ToStateEstimate(p, *frame);
    // A batch or lagged state of a local start stays local though the run went on into ENU.
    if (out)
      out->status = local ? EstimateStatus::kLocal : StatusAt(ctx.diag, position_sensors, t_ns);
    return out;
  }

  // ---- 4. Solve ------------------------------------------------------------------------------

  void Solve() {
    const auto start = std::chrono::steady_clock::now();
    const SmootherSolveSummary summary = ctx.smoother.Solve();
    std::vector<NavState> left = ctx.smoother.TakeMarginalizedStates();
    const NavState newest = ctx.smoother.NewestState();
    const Mat15 covariance = ctx.smoother.NewestCovariance();
    const auto stop = std::chrono::steady_clock::now();
    ctx.diag.updates.Add(SolveDiagnostics(summary, newest.t_ns,
                                          std::chrono::duration<double>(stop - start).count()));

    ctx.RecordGlobals();
    for (MeasurementFrontEnd* f : front_ends) f->OnMarginalized(left);
    if (keep_smoothed) smoothed.insert(smoothed.end(), left.begin(), left.end());
    if (newest.q_world_imu.coeffs().allFinite() && newest.p_world.allFinite() &&
        newest.v_world.allFinite() && covariance.allFinite()) {
      MoveAnchor(PropagatedState{newest, covariance});
    }
    const TimeNs interval = FromSeconds(options.solve_interval_s);
    while (next_solve_ns <= lagged_ns) next_solve_ns += interval;
    // The IMU-rate output keeps what the window and the front ends still need.
    TimeNs keep = ctx.smoother.WindowStates().front().t_ns;
    for (const MeasurementFrontEnd* f : front_ends) keep = std::min(keep, f->OldestStampNeeded());
    ctx.output.Forget(keep);
  }

  // The new anchor; the output continues from what it showed at the newest sample and blends
  // the correction in (output_blend.hpp).
  void MoveAnchor(const PropagatedState& anchor) {
    const TimeNs now = ctx.newest_imu_ns;
    const std::optional<PropagatedState> before = ctx.output.AfterAnchor(now);
    ctx.output.SetAnchor(anchor);
    const std::optional<PropagatedState> after = ctx.output.AfterAnchor(now);
    if (before && after) {
      blend.Rebase(blend.Apply(*before).state, after->state);
    } else {
      blend.Reset();
    }
  }
};

FactorGraphEstimator::FactorGraphEstimator(const EstimatorSensorSetup& setup,
                                           const FactorGraphOptions& options,
                                           LidarOdometryPool* lidar_pool) {
  std::string why;
  if (!options.IsValid(&why)) throw InputError(why);
  impl_ = std::make_unique<Impl>(setup, options, lidar_pool);
}

FactorGraphEstimator::~FactorGraphEstimator() = default;

void FactorGraphEstimator::Add(const Measurement& measurement) { impl_->Add(measurement); }

std::optional<StateEstimate> FactorGraphEstimator::StateAt(TimeNs t_ns) const {
  if (EstimatesAtEnd()) return impl_->BatchStateAt(t_ns);
  std::optional<PropagatedState> p = impl_->ctx.PredictAt(t_ns);
  if (!p) return std::nullopt;
  // The calibration share at the best estimate; the blend's offset on top (output_blend.hpp).
  const Mat15 consider = impl_->CalibrationConsider(p->state);
  *p = impl_->blend.Apply(*p);
  p->covariance += consider;
  return impl_->Present(*p, impl_->ctx.local_frame, t_ns);
}

EstimatorDiagnostics FactorGraphEstimator::diagnostics() const {
  EstimatorDiagnostics d = impl_->ctx.diag;
  if (!impl_->ctx.initialized) d.waiting_for = impl_->ctx.initializer.WaitingFor();
  return d;
}

void FactorGraphEstimator::SetVerdictObserver(VerdictObserver observer) {
  impl_->ctx.verdicts = std::move(observer);
}

bool FactorGraphEstimator::EstimatesAtEnd() const {
  return impl_->options.batch || impl_->options.lagged_output;
}

void FactorGraphEstimator::EndOfLog() { impl_->EndOfLog(); }

void FactorGraphEstimator::KeepSmoothedStates() { impl_->keep_smoothed = true; }

std::vector<NavState> FactorGraphEstimator::TakeSmoothedStates() {
  std::vector<NavState> out;
  out.swap(impl_->smoothed);
  return out;
}

std::optional<GeodeticPoint> FactorGraphEstimator::origin() const {
  const std::optional<LocalEnuFrame>& frame = impl_->front_end_set.gnss->frame();
  if (!frame) return std::nullopt;
  return frame->origin();
}

}  // namespace statebench::est
