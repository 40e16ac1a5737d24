#include "reports/run_scorer.hpp"

#include <algorithm>

namespace statebench::reports {
namespace {

bool Finite(const NavState& s) {
  return s.p_world.allFinite() && s.v_world.allFinite() && s.q_world_imu.coeffs().allFinite();
}

// Comparable with the truth: finite and in the world frame (a local frame's estimate is not).
bool InWorldFrame(const NavState& s, EstimateStatus status) {
  return Finite(s) && status != EstimateStatus::kLocal;
}

double Ratio(std::size_t a, std::size_t b) {
  return b > 0 ? static_cast<double>(a) / static_cast<double>(b) : 0.0;
}

}  // namespace

double Availability::Fraction() const { return Ratio(finite_estimates, epochs); }
double Availability::SpanFraction() const { return Ratio(span_finite_estimates, span_epochs); }

RunScorer::RunScorer(std::size_t estimators, const SE3& T_body_frame, RunScoringOptions options)
    : options_(std::move(options)), track_(T_body_frame) {
  options_.metrics.skip_before_ns = 0;  // the span decides
  MetricsOptions window_options = options_.metrics;
  window_options.outages.clear();
  for (std::size_t k = 0; k < estimators; ++k) {
    PerEstimator e{TrajectoryScorer(options_.metrics), {}, {}, std::nullopt};
    for (std::size_t w = 0; w < options_.metrics.outages.size(); ++w) {
      e.outage_scorers.emplace_back(window_options);
    }
    estimators_.push_back(std::move(e));
  }
}

void RunScorer::AddTruth(const TruthSample& sample) {
  track_.Add(sample);
  while (!waiting_for_truth_.empty() && waiting_for_truth_.front().t_ns <= track_.newest_ns()) {
    Pair(waiting_for_truth_.front());
    waiting_for_truth_.pop_front();
  }
}

void RunScorer::AddEpoch(TimeNs t_ns,
                         const std::vector<std::optional<StateEstimate>>& estimates) {
  Epoch epoch;
  epoch.t_ns = t_ns;
  epoch.estimates.resize(estimators_.size());
  bool any = false;
  for (std::size_t k = 0; k < estimators_.size() && k < estimates.size(); ++k) {
    Availability& a = estimators_[k].availability;
    ++a.epochs;
    if (!estimates[k]) continue;
    ++a.estimates;
    const NavState& s = estimates[k]->state;
    if (Finite(s)) {
      ++a.finite_estimates;
      if (!first_epoch_ns_) first_epoch_ns_ = t_ns;
    }
    if (InWorldFrame(s, estimates[k]->status) && !estimators_[k].first_world_ns) {
      estimators_[k].first_world_ns = t_ns;
    }
    epoch.estimates[k] = ScoredEstimate::Of(*estimates[k]);
    any = true;
  }
  DecideSpan(t_ns, false);
  // Before any estimator has started, an epoch is before the span whatever it will be: only
  // counted (above), not held, and the truth up to it is not needed any more.
  if (!any && !span_begin_ns_ && !first_epoch_ns_) {
    if (observer_ && !track_.empty() && t_ns <= track_.newest_ns()) {
      if (const auto reference = track_.At(t_ns)) {
        observer_(*reference, std::vector<std::optional<EpochErrors>>(estimators_.size()));
      }
    }
    track_.DropBefore(t_ns);
    return;
  }
  if (!track_.empty() && t_ns <= track_.newest_ns()) {
    Pair(epoch);
  } else {
    waiting_for_truth_.push_back(std::move(epoch));
  }
}

void RunScorer::Pair(const Epoch& epoch) {
  const std::optional<ReferenceState> reference = track_.At(epoch.t_ns);
  track_.DropBefore(epoch.t_ns);
  if (span_begin_ns_) {
    Score(epoch, reference);
  } else {
    before_span_.emplace_back(epoch, reference);
  }
}

void RunScorer::DecideSpan(TimeNs now_ns, bool at_end) {
  if (span_begin_ns_ || !first_epoch_ns_) return;
  const bool all_started =
      std::all_of(estimators_.begin(), estimators_.end(),
                  [](const PerEstimator& e) { return e.first_world_ns.has_value(); });
  if (!all_started && !at_end && now_ns - *first_epoch_ns_ < options_.span_wait_ns) return;
  TimeNs begin = *first_epoch_ns_;
  for (const PerEstimator& e : estimators_) {
    if (e.first_world_ns) begin = std::max(begin, *e.first_world_ns);
  }
  span_begin_ns_ = begin;
  for (const auto& [epoch, reference] : before_span_) Score(epoch, reference);
  before_span_.clear();
  before_span_.shrink_to_fit();
}

void RunScorer::Score(const Epoch& epoch, const std::optional<ReferenceState>& reference) {
  const bool in_span = reference && epoch.t_ns >= *span_begin_ns_;
  if (observer_ && reference) {
    std::vector<std::optional<EpochErrors>> errors(estimators_.size());
    for (std::size_t k = 0; k < estimators_.size(); ++k) {
      const std::optional<ScoredEstimate>& c = epoch.estimates[k];
      if (!in_span || !c || !InWorldFrame(c->state, c->status)) continue;
      errors[k] = EpochErrorsOf(c->state, c->status, c->pose_covariance, c->velocity_covariance,
                                *reference);
    }
    observer_(*reference, errors);
  }
  for (std::size_t k = 0; k < estimators_.size(); ++k) {
    PerEstimator& e = estimators_[k];
    const std::optional<ScoredEstimate>& c = epoch.estimates[k];
    const bool local = c && c->status == EstimateStatus::kLocal;
    if (in_span) {
      ++e.availability.span_epochs;
      if (c && local) ++e.availability.span_local_estimates;
      if (c && InWorldFrame(c->state, c->status)) ++e.availability.span_finite_estimates;
    }
    // No estimate at this epoch, or a change of frame (a local start moved into ENU): no output
    // step across it.
    if (!c || local != e.last_local) {
      e.scorer.Break();
      for (TrajectoryScorer& w : e.outage_scorers) w.Break();
    }
    e.last_local = local;
    if (!c) continue;
    if (!in_span || local) {
      e.scorer.Skip();
      continue;
    }
    e.scorer.Add(c->state, c->pose_covariance, *reference);
    for (std::size_t w = 0; w < e.outage_scorers.size(); ++w) {
      const OutageWindow& window = options_.metrics.outages[w];
      if (epoch.t_ns >= window.begin_ns && epoch.t_ns <= window.end_ns) {
        e.outage_scorers[w].Add(c->state, c->pose_covariance, *reference);
      }
    }
  }
}

std::vector<RunScore> RunScorer::Finish() {
  DecideSpan(0, true);
  if (!span_begin_ns_) span_begin_ns_ = first_epoch_ns_.value_or(0);
  for (const auto& [epoch, reference] : before_span_) Score(epoch, reference);
  before_span_.clear();
  for (const Epoch& epoch : waiting_for_truth_) Score(epoch, std::nullopt);  // beyond the truth
  waiting_for_truth_.clear();
  std::vector<RunScore> out;
  for (PerEstimator& e : estimators_) {
    RunScore s;
    s.metrics = e.scorer.Finish();
    for (TrajectoryScorer& w : e.outage_scorers) s.during_outages.push_back(w.Finish());
    s.availability = e.availability;
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace statebench::reports
