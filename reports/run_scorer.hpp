// Scores every estimator of one run against the truth while the run goes, over one common span,
// in memory that does not grow with the run's length.
//
// The span: from the latest first world-frame estimate of the run's estimators to the end of the
// truth. It is decided once every estimator has given a finite estimate in the world frame, or
// `span_wait_ns` after the first output epoch, whichever comes first; an estimator that starts
// later than that is scored from the span's start all the same, its missing epochs counted as
// unavailable. An estimate with the status `local` (a local frame: no GNSS in the setup, or a
// factor graph that started before its fixes gave the yaw) is not in the truth's frame and is
// never compared with it: before the span it is skipped like any other, inside it counted as
// `span_local_estimates`, not as a finite estimate, and skipped. Until the span is
// decided the paired epochs are held (state, pose and velocity covariance, ~0.6 KB per estimator
// and epoch; 2 minutes at most). So no estimator is scored over an easier stretch than
// another, and what an estimator did not deliver is counted, not hidden.
//
// Truth comes at its own rate (AddTruth, stamps increasing, ahead of or behind the estimates);
// an epoch is scored once the truth reaches its stamp, and the truth before it is dropped.
#pragma once

#include <cstddef>
#include <deque>
#include <functional>
#include <optional>
#include <vector>

#include "core/state.hpp"
#include "reports/epoch_errors.hpp"
#include "reports/reference_track.hpp"
#include "reports/trajectory_scorer.hpp"

namespace statebench::reports {

struct RunScoringOptions {
  MetricsOptions metrics;  // skip_before_ns is set by the span
  TimeNs span_wait_ns = 120 * kNsPerSecond;
};

// What an estimator delivered at the output epochs (IMU stamps) it was offered.
struct Availability {
  std::size_t epochs = 0;             // output epochs offered (the whole run)
  std::size_t estimates = 0;          // epochs with an estimate
  std::size_t finite_estimates = 0;   // ... with a finite mean
  std::size_t span_epochs = 0;        // epochs inside the scored span
  std::size_t span_finite_estimates = 0;  // ... finite and in the world frame
  std::size_t span_local_estimates = 0;   // ... in a local frame (not compared)
  double Fraction() const;            // finite_estimates / epochs
  double SpanFraction() const;        // span_finite_estimates / span_epochs
};

struct RunScore {
  TrajectoryMetrics metrics;
  std::vector<TrajectoryMetrics> during_outages;  // one per metrics.outages window
  Availability availability;
};

// What the scorer reads of an estimate (~0.5 KB instead of a StateEstimate's 2): the state, its
// status, the pose and velocity covariance blocks. Also what a run holds of an estimate until
// the scorer takes it (apps/estimator_feed.hpp).
struct ScoredEstimate {
  NavState state;
  EstimateStatus status;
  Mat6 pose_covariance;
  Mat3 velocity_covariance;

  static ScoredEstimate Of(const StateEstimate& e) {
    return {e.state, e.status, e.covariance.topLeftCorner<6, 6>(),
            e.covariance.block<3, 3>(kVelocityIndex, kVelocityIndex)};
  }
  // Back to an estimate: the other covariance blocks zero (the scorer does not read them).
  StateEstimate ToStateEstimate() const {
    StateEstimate e;
    e.status = status;
    e.state = state;
    e.covariance.setZero();
    e.covariance.topLeftCorner<6, 6>() = pose_covariance;
    e.covariance.block<3, 3>(kVelocityIndex, kVelocityIndex) = velocity_covariance;
    return e;
  }
};

class RunScorer {
 public:
  RunScorer(std::size_t estimators, const SE3& T_body_frame, RunScoringOptions options);

  // Called for every epoch paired with the truth, in stamp order (the span may be decided up to
  // span_wait_ns later): the reference there and, per estimator, the errors of its estimate when
  // it is inside the scored span (nullopt otherwise).
  using EpochObserver = std::function<void(const ReferenceState& reference,
                                           const std::vector<std::optional<EpochErrors>>& errors)>;
  void SetEpochObserver(EpochObserver observer) { observer_ = std::move(observer); }

  void AddTruth(const TruthSample& sample);

  // One output epoch: the estimate of each estimator (nullopt: none), in the order they were
  // counted in the constructor.
  void AddEpoch(TimeNs t_ns, const std::vector<std::optional<StateEstimate>>& estimates);

  // Scores what is left (epochs beyond the truth are skipped) and returns one score per
  // estimator.
  std::vector<RunScore> Finish();

  // The span's start once decided (the latest first world-frame estimate), nullopt before.
  std::optional<TimeNs> span_begin_ns() const { return span_begin_ns_; }

 private:
  struct Epoch {
    TimeNs t_ns = 0;
    std::vector<std::optional<ScoredEstimate>> estimates;
  };
  struct PerEstimator {
    TrajectoryScorer scorer;
    std::vector<TrajectoryScorer> outage_scorers;
    Availability availability;
    std::optional<TimeNs> first_world_ns;  // the first finite estimate not in a local frame
    bool last_local = false;  // the last estimate's status was local
  };

  void Pair(const Epoch& epoch);  // the truth covers it
  void Score(const Epoch& epoch, const std::optional<ReferenceState>& reference);
  void DecideSpan(TimeNs now_ns, bool at_end);

  RunScoringOptions options_;
  EpochObserver observer_;
  ReferenceTrack track_;
  std::vector<PerEstimator> estimators_;
  std::deque<Epoch> waiting_for_truth_;
  std::deque<std::pair<Epoch, std::optional<ReferenceState>>> before_span_;
  std::optional<TimeNs> first_epoch_ns_;
  std::optional<TimeNs> span_begin_ns_;
};

}  // namespace statebench::reports
