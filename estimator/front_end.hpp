// The factor graph's front ends: each turns the measurements of one kind of sensor into factors
// of the sliding-window smoother (GNSS fixes and headings, encoders, motion constraints, lidar).
//
// The orchestrator (FactorGraphEstimator) releases measurements in stamp order and hands each one
// to the front end that takes it; a front end owns all of its own state and reaches the rest of
// the estimator only through FrontEndContext. Hooks a front end does not need keep their empty
// defaults. Adding a measurement kind means writing a front end and registering it with the
// orchestrator (FactorGraphEstimator::Impl::front_ends); the intake finds it through Claims().
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/measurements.hpp"
#include "core/state.hpp"
#include "core/time.hpp"
#include "estimator/enu_alignment.hpp"
#include "estimator/estimator_diagnostics.hpp"
#include "estimator/imu_noise_monitor.hpp"
#include "estimator/imu_rate_output.hpp"
#include "estimator/sliding_window_smoother.hpp"
#include "estimator/state_initializer.hpp"

namespace statebench::est {

// What a front end sees of the estimator: the smoother it adds factors to, the initialiser it
// feeds before the first state, the state predicted at a stamp (gates, deskewing) and the
// per-sensor counters of the diagnostics. Owned by the orchestrator.
class FrontEndContext {
 public:
  // forward_imu: the vehicle's forward axis in the IMU frame (for the moving initialisation);
  // local: how a setup without an absolute-position sensor starts.
  FrontEndContext(const SlidingWindowOptions& smoother_options,
                  const InitializationOptions& initialization, const ImuNoise& noise,
                  const Vec3& forward_imu, LocalStart local = {},
                  const ImuNoiseEstimationOptions& noise_estimation = {})
      : smoother(smoother_options),
        initializer(initialization, noise, forward_imu, local),
        output(noise),
        smoother_options_(smoother_options),
        initialization_(initialization),
        noise_(noise),
        forward_imu_(forward_imu),
        local_(local),
        noise_monitor_(noise_estimation, noise) {
    diag.imu_noise = noise_monitor_.report();
  }

  SlidingWindowSmoother smoother;
  StateInitializer initializer;
  ImuRateOutput output;  // IMU-rate propagation from the newest solved state
  EstimatorDiagnostics diag;
  bool initialized = false;
  TimeNs newest_imu_ns = INT64_MIN;  // newest accepted IMU sample (not yet released)
  // Set by a front end that finds the estimate lost; the orchestrator then starts over.
  bool lost = false;
  // The estimate is in a local frame while the setup has a GNSS antenna (LocalStart::enu_later):
  // the GNSS front end aligns the local track with the fixes and, once they give the yaw, sets
  // enu_switch; the orchestrator then moves the estimate into ENU.
  bool local_frame = false;
  std::optional<EnuAlignment::Result> enu_switch;

  // Starts over: an empty smoother and initialiser, no output until initialised again (the
  // counters and the diagnostics stay).
  void Restart() {
    RestartSmoother();
    initializer = StateInitializer(initialization_, noise_, forward_imu_, local_);
    output = ImuRateOutput(noise_);
    initialized = false;
    lost = false;
    local_frame = false;
    enu_switch.reset();
  }

  // An empty smoother (the orchestrator initialises it again); it has no globals.
  void RestartSmoother() {
    std::destroy_at(&smoother);
    std::construct_at(&smoother, smoother_options_);
    globals_.clear();
  }

  // A global of the window (SlidingWindowSmoother::AddGlobal) that belongs to a sensor, `name`
  // with its unit ("time_offset_s", "mount_yaw_rad"): created with its prior by the first front
  // end that asks, the same index for every one asking after that (the IMU mount's corrections
  // serve the non-holonomic and the kinematic factors), until the smoother restarts. Its
  // estimate goes to the sensor's diagnostics (SensorCounters::globals) at RecordGlobals.
  // correlation_time_s: a first-order Gauss-Markov process (AddGlobal).
  int Global(const std::string& sensor_id, const std::string& name, double prior_sigma,
             double max_abs, std::optional<double> correlation_time_s = std::nullopt);
  std::optional<int> FindGlobal(const std::string& sensor_id, const std::string& name) const;
  // A sensor frame's mount rotation correction (SlidingWindowSmoother::MountCorrection) as the
  // globals "mount_pitch_rad", "mount_yaw_rad" (and "mount_roll_rad" with_roll) of the sensor,
  // each with the prior N(0, prior_sigma_rad^2), held within +-max_rad.
  SlidingWindowSmoother::MountCorrection MountGlobals(const std::string& sensor_id,
                                                      double prior_sigma_rad, double max_rad,
                                                      bool with_roll);
  // The current estimate of a sensor's mount correction (roll, pitch, yaw; 0 where none).
  Vec3 MountEstimate(const std::string& sensor_id) const;
  // After every solve: each global's value, sigma and bound count into its sensor's
  // diagnostics, with a history sample every kGlobalHistoryPeriodS.
  void RecordGlobals();

  // The IMU noise the smoother and the output use from now on, and after a restart (the
  // measured one, imu_noise_monitor.hpp).
  void SetImuNoise(const ImuNoise& noise) {
    smoother.SetImuNoise(noise);
    output.SetNoise(noise);
    smoother_options_.imu_noise = noise;
    noise_ = noise;
  }
  const ImuNoise& imu_noise() const { return noise_; }

  // The samples of a window the standstill test passed: the noise measured on them inflates the
  // one in use when it is well above the datasheet's (imu_noise_monitor.hpp).
  template <typename Samples>
  void MeasureStillImu(const Samples& window) {
    bool changed = false;
    for (const ImuSample& s : window) changed = noise_monitor_.AddStill(s) || changed;
    if (changed) SetImuNoise(noise_monitor_.used());
    diag.imu_noise = noise_monitor_.report();
  }

  // Mean and covariance at t_ns: propagated from the newest solved state, or inside the window
  // (mean from the states around t, covariance of the newest state); nullopt if not held.
  std::optional<PropagatedState> PredictAt(TimeNs t_ns) const {
    if (const auto p = output.AfterAnchor(t_ns, smoother.FromNewestState())) return p;
    if (!output.has_anchor() || t_ns > newest_imu_ns) return std::nullopt;
    const std::vector<NavState> window = smoother.WindowStates();
    return output.InWindow(t_ns, window);
  }
  // PredictAt's mean and the velocity block of its covariance alone, the same bits.
  std::optional<PropagatedVelocity> PredictVelocityAt(TimeNs t_ns) const {
    if (const auto p = output.VelocityAfterAnchor(t_ns, smoother.FromNewestState())) return p;
    if (!output.has_anchor() || t_ns > newest_imu_ns) return std::nullopt;
    const std::vector<NavState> window = smoother.WindowStates();
    return output.VelocityInWindow(t_ns, window);
  }
  // PredictAt's mean alone, the same bits, without carrying the covariance where it can be
  // left out (after the anchor), for the front ends that read only the mean.
  std::optional<NavState> PredictMeanAt(TimeNs t_ns) const {
    if (const auto mean = output.MeanAfterAnchor(t_ns, smoother.FromNewestState())) return mean;
    if (const auto p = PredictAt(t_ns)) return p->state;
    return std::nullopt;
  }

  SensorCounters& Counters(const std::string& id) { return diag.sensors[id]; }
  VerdictObserver verdicts;  // optional (Estimator::SetVerdictObserver)
  void Accept(const std::string& id, TimeNs t_ns) { diag.Verdict(id, t_ns, std::nullopt, verdicts); }
  void Reject(const std::string& id, TimeNs t_ns, RejectReason reason) {
    diag.Verdict(id, t_ns, reason, verdicts);
  }
  void Count(const std::string& id, const std::string& event) { ++Counters(id).events[event]; }

 private:
  SlidingWindowOptions smoother_options_;
  InitializationOptions initialization_;
  ImuNoise noise_;
  Vec3 forward_imu_;
  LocalStart local_;
  ImuNoiseMonitor noise_monitor_;  // kept across restarts, as the noise it measured
  std::map<std::pair<std::string, std::string>, int> globals_;  // (sensor, name) -> index
};

// How a front end answers for a measurement: not its kind, its kind from a sensor the setup does
// not have as such, or taken (whether or not the front end is enabled: a disabled one rejects
// what it takes, counted as "disabled").
enum class Claim { kOtherKind, kUnknownSensor, kTaken };

class MeasurementFrontEnd {
 public:
  virtual ~MeasurementFrontEnd() = default;

  virtual Claim Claims(const Measurement& m) const = 0;
  // Measurements of one stamp are handed over in two passes, each in stamp-then-stream order:
  // pass 0 first (e.g. a steering angle that the speed sample of the same stamp needs), then 1.
  virtual int Pass(const Measurement& m) const { return 1; }
  // A released measurement this front end takes (in stamp order; late ones after the fact).
  virtual void Process(const Measurement& m) = 0;
  // After every measurement of one stamp was handed over (GNSS pairs the fixes of a stamp).
  virtual void EndOfStamp() {}
  // Every IMU sample, as it is released to the smoother.
  virtual void OnImu(const ImuSample& sample) {}
  // After each release of measurements (e.g. scans waiting for the IMU to cover their sweep).
  virtual void AfterRelease() {}
  // Before the first state is set: may refine it with what this front end knows.
  virtual void RefineInitialState(const ImuSample& sample, InitialState* init) const {}
  virtual void OnInitialized(const InitialState& init) {}
  // The estimator starts over (lost): forget what refers to the old window's states.
  virtual void OnRestart() {}
  // After a solve: the states that left the window (final), oldest first.
  virtual void OnMarginalized(std::span<const NavState> left) {}
  // The oldest stamp whose IMU-rate propagation this front end still needs.
  virtual TimeNs OldestStampNeeded() const { return INT64_MAX; }
};

}  // namespace statebench::est
