// What an estimator reports about itself: per update (solve time, iterations, factors by type)
// and per sensor (measurements accepted, rejected by reason, down-weighted by a robust kernel).
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/running_statistics.hpp"
#include "core/time.hpp"
#include "estimator/imu_noise_monitor.hpp"

namespace statebench::est {

enum class RejectReason {
  kNonFinite,            // NaN or infinite value
  kAbsurdValue,          // finite but physically impossible (e.g. 100 g, latitude 91 deg)
  kStampBackwards,       // IMU stamp not after the previous one, or a repeated stamp of a sensor
  kStampInFuture,        // stamp after the newest arrival stamp, or far ahead of the IMU
  kUnknownSensor,        // sensor id not in the sensor setup (or of the wrong type)
  kUnsupportedSensor,    // configured, but not used by this estimator (yet): lidar, encoders
  kNoFix,                // GNSS status "no fix"
  kInvalidCovariance,    // reported covariance not symmetric positive definite
  kCovarianceThreshold,  // reported uncertainty above the configured threshold (paper)
  kMahalanobisGate,      // innovation beyond the chi-square gate
  kTooOld,               // older than the oldest state the estimator still holds
  kNotInitialized,       // arrived before initialisation and was not needed for it
  kDisabled,             // the factor using it is switched off in the estimator options
  kRegistrationFailed,   // lidar scan not registered (empty, too few points, ICP failure);
                         // the detail is counted in SensorCounters::events
  kSaturated,            // IMU sample beyond the estimator's imu_limits (saturated or implausible)
};

std::string_view RejectReasonName(RejectReason reason);

// Receives every verdict an estimator gives a measurement, when it gives it: the sensor, the
// measurement's stamp and why it was rejected (nullopt: accepted). `statebench run` writes them
// per estimator for the run report.
using VerdictObserver = std::function<void(const std::string& sensor_id, TimeNs stamp_ns,
                                           std::optional<RejectReason> rejected)>;

// A global of the window that belongs to a sensor as the smoother estimates it
// (FrontEndContext::Global): a GNSS receiver's time offset to the IMU (gnss.estimate_time_offset;
// s, sign: gnss_time_offset_factor.hpp), a mount's rotation correction (rad).
struct GlobalDiagnostics {
  double value = 0.0;
  double sigma = 0.0;  // marginal of the last solve
  int clamped = 0;     // solves after which it was held at its bound
  struct Sample {
    TimeNs t_ns = 0;
    double value = 0.0;
    double sigma = 0.0;
  };
  std::vector<Sample> history;  // one per kGlobalHistoryPeriodS of solves
};
inline constexpr double kGlobalHistoryPeriodS = 1.0;

struct SensorCounters {
  std::uint64_t received = 0;
  std::uint64_t accepted = 0;
  std::map<RejectReason, std::uint64_t> rejected;
  // Accepted measurements whose whitened residual at the final estimate exceeded the robust
  // kernel's scale (their weight was reduced, not zeroed); counted when they leave the window.
  std::uint64_t downweighted = 0;
  // Sensor-specific events with their counts, e.g. a lidar's "degenerate" registrations or
  // "empty scan" rejections, an encoder's "integration restarted" after a gap.
  std::map<std::string, std::uint64_t> events;
  TimeNs last_accepted_ns = 0;  // stamp of the newest accepted measurement (0: none)
  // The factor the estimator applies to the reported covariance, when it adapts it (GNSS
  // positions: innovation_scale.hpp); nullopt while it never changed from 1.
  std::optional<double> covariance_scale;
  // The sensor's globals by name with unit ("time_offset_s", "mount_pitch_rad"), when estimated.
  std::map<std::string, GlobalDiagnostics> globals;

  // Counts an accepted measurement stamped stamp_ns.
  void Accept(TimeNs stamp_ns);
  std::uint64_t TotalRejected() const;
};

struct UpdateDiagnostics {
  TimeNs t_ns = 0;            // stamp of the newest state of the update
  double solve_time_s = 0.0;  // wall clock: optimisation, marginalisation and covariance
  int iterations = 0;
  bool usable = false;  // the solver returned a usable solution
  int num_states = 0;
  int num_marginalized = 0;
  bool marginalization_deferred = false;  // not usable: the window waits for a usable solve
  int num_marginalized_unusable = 0;      // marginalised all the same (window at its limit)
  int num_left_out_of_prior = 0;          // factors not finite when their state was marginalised
  // by type: "prior", "imu", "bias", "gnss", "heading", "relative_pose", "velocity"
  std::map<std::string, int> factors;
};

// Every update counted and its solve time summarised, the most recent updates kept whole: the
// diagnostics of an hour's run are the size of a minute's.
class UpdateLog {
 public:
  static constexpr std::size_t kRecent = 1000;  // updates kept whole
  static constexpr double kPeriodS = 60.0;      // solve-time summaries per period of stamps

  // Solve time summary of one period of update stamps: [start_s, start_s + kPeriodS).
  struct Period {
    double start_s = 0.0;
    std::uint64_t count = 0;
    double median_ms = 0.0, p99_ms = 0.0, max_ms = 0.0;
  };

  void Add(const UpdateDiagnostics& u);

  std::uint64_t count() const { return count_; }
  bool empty() const { return count_ == 0; }
  std::uint64_t unusable() const { return unusable_; }
  // Updates whose marginalisation waited for a usable solve, and states marginalised at an
  // unusable solve's point because the window reached its limit.
  std::uint64_t deferred_marginalizations() const { return deferred_; }
  std::uint64_t marginalized_unusable() const { return marginalized_unusable_; }
  std::uint64_t left_out_of_prior() const { return left_out_of_prior_; }
  double mean_iterations() const;
  // Solve times of every update, ms.
  const RunningStatistics& solve_ms() const { return solve_ms_; }
  // The last kRecent updates, oldest first.
  const std::deque<UpdateDiagnostics>& recent() const { return recent_; }
  // How many updates had at least one factor of each type.
  const std::map<std::string, std::uint64_t>& with_factor() const { return with_factor_; }
  // One summary per period of stamps since the first update, the current one included.
  std::vector<Period> Periods() const;

 private:
  Period CurrentPeriod() const;

  std::uint64_t count_ = 0, unusable_ = 0, deferred_ = 0, marginalized_unusable_ = 0,
                left_out_of_prior_ = 0;
  double iterations_ = 0.0;
  RunningStatistics solve_ms_;
  std::deque<UpdateDiagnostics> recent_;
  std::map<std::string, std::uint64_t> with_factor_;
  std::vector<Period> closed_;
  std::optional<TimeNs> first_ns_;
  RunningStatistics period_ms_;
  double period_start_s_ = 0.0;
};

// One time the estimator found itself lost and started over from the sensors.
struct LostEpisode {
  TimeNs at_ns = 0;
  std::string reason;                      // "lost" (the GNSS track) or "imu_gap"
  std::optional<TimeNs> reinitialized_ns;  // nullopt while it re-initialises
  std::string reinitialization;            // how, e.g. "moving (gnss course)"
};

// A start in a local frame moved into ENU (a setup with GNSS whose yaw was not observable at
// the start: enu_alignment.hpp). Estimates before at_ns are in the local frame (status `local`).
struct EnuSwitch {
  TimeNs at_ns = 0;
  int fixes = 0;         // aligned against the local track
  double span_m = 0.0;   // their largest distance from their centroid
  double yaw_rad = 0.0;  // p_enu = Rz(yaw) p_local + translation
  std::array<double, 3> translation_m = {0.0, 0.0, 0.0};
  double yaw_sigma_rad = 0.0;
  double sigma_h_m = 0.0;           // per fix and horizontal axis, as used
  double residual_sigma_h_m = 0.0;  // from the fit's residuals
};

// One full-batch solve (FactorGraphOptions::batch): every state of one smoother run, from its
// initialisation (or the last restart) to the end of the log or the next restart.
struct BatchSolve {
  TimeNs begin_ns = 0;  // the first and last state
  TimeNs end_ns = 0;
  int states = 0;
  int iterations = 0;
  double initial_cost = 0.0;  // at the fixed-lag estimates
  double final_cost = 0.0;
  bool usable = false;  // else the run has no estimate over [begin_ns, end_ns]
  double solve_s = 0.0;
};

struct EstimatorDiagnostics {
  bool initialized = false;
  TimeNs initialized_at_ns = 0;
  std::string initialization;  // how: "static", "moving (dual antenna)", "moving (gnss course)"
  // While the estimator has no state (never initialised, or re-initialising after it was lost):
  // what it is waiting for, one line naming the test that failed and its figures, e.g. "no still
  // period of 1 s (quietest window: gyro std 0.04 rad/s > 0.01) and no GNSS course (2 fixes)".
  // Empty while it has a state.
  std::string waiting_for;
  // What the estimator lacks or takes on trust in its setup, known before it runs (e.g. the
  // EKF without a speed input, or with a vehicle file whose axles are not where the encoders
  // are). One sentence each.
  std::vector<std::string> warnings;
  // Times the estimator found itself lost and started over from the sensors (every GNSS fix
  // gated out for longer than gate_reset_s while the fixes agreed with each other, or an IMU
  // gap), and how it re-initialised each time.
  std::vector<LostEpisode> lost;
  // The estimate is in a local frame now (a setup without GNSS, or one whose start came before
  // the GNSS could give the yaw), and each time such a start moved into ENU.
  bool local_frame = false;
  std::vector<EnuSwitch> enu_switches;
  // The IMU noise measured and used (imu_noise_monitor.hpp); the factor graph's only.
  std::optional<ImuNoiseReport> imu_noise;
  std::map<std::string, SensorCounters> sensors;  // by sensor id, unknown ids included
  UpdateLog updates;
  std::vector<BatchSolve> batch_solves;  // the full-batch smoother's, when it is on

  // Records an initialisation at t_ns: the first one, or the end of the open lost episode.
  void Initialized(TimeNs t_ns, const std::string& method);
  // Opens a lost episode.
  void Lost(TimeNs t_ns, const std::string& reason) { lost.push_back({t_ns, reason, {}, {}}); }
  // Counts the verdict on a measurement of sensor `id` stamped t_ns (reason nullopt: accepted)
  // and hands it to the observer when there is one.
  void Verdict(const std::string& id, TimeNs t_ns, std::optional<RejectReason> reason,
               const VerdictObserver& observer);
  // The stamp of the newest (re-)initialisation, nullopt before the first.
  std::optional<TimeNs> LatestInitializationNs() const;
};

}  // namespace statebench::est
