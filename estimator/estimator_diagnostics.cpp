#include "estimator/estimator_diagnostics.hpp"

#include <algorithm>
#include <cmath>

namespace statebench::est {

std::string_view RejectReasonName(RejectReason reason) {
  switch (reason) {
    case RejectReason::kNonFinite:
      return "non_finite";
    case RejectReason::kAbsurdValue:
      return "absurd_value";
    case RejectReason::kStampBackwards:
      return "stamp_backwards";
    case RejectReason::kStampInFuture:
      return "stamp_in_future";
    case RejectReason::kUnknownSensor:
      return "unknown_sensor";
    case RejectReason::kUnsupportedSensor:
      return "unsupported_sensor";
    case RejectReason::kNoFix:
      return "no_fix";
    case RejectReason::kInvalidCovariance:
      return "invalid_covariance";
    case RejectReason::kCovarianceThreshold:
      return "covariance_threshold";
    case RejectReason::kMahalanobisGate:
      return "mahalanobis_gate";
    case RejectReason::kTooOld:
      return "too_old";
    case RejectReason::kNotInitialized:
      return "not_initialized";
    case RejectReason::kDisabled:
      return "disabled";
    case RejectReason::kRegistrationFailed:
      return "registration_failed";
    case RejectReason::kSaturated:
      return "saturated";
  }
  return "unknown";
}

void SensorCounters::Accept(TimeNs stamp_ns) {
  ++accepted;
  last_accepted_ns = std::max(last_accepted_ns, stamp_ns);
}

std::uint64_t SensorCounters::TotalRejected() const {
  std::uint64_t n = 0;
  for (const auto& [reason, count] : rejected) n += count;
  return n;
}

void EstimatorDiagnostics::Verdict(const std::string& id, TimeNs t_ns,
                                   std::optional<RejectReason> reason,
                                   const VerdictObserver& observer) {
  SensorCounters& c = sensors[id];
  if (reason) {
    ++c.rejected[*reason];
  } else {
    c.Accept(t_ns);
  }
  if (observer) observer(id, t_ns, reason);
}

void EstimatorDiagnostics::Initialized(TimeNs t_ns, const std::string& method) {
  if (!initialized) {
    initialized = true;
    initialized_at_ns = t_ns;
    initialization = method;
  } else if (!lost.empty() && !lost.back().reinitialized_ns) {
    lost.back().reinitialized_ns = t_ns;
    lost.back().reinitialization = method;
  }
}

std::optional<TimeNs> EstimatorDiagnostics::LatestInitializationNs() const {
  if (!initialized) return std::nullopt;
  for (auto it = lost.rbegin(); it != lost.rend(); ++it) {
    if (it->reinitialized_ns) return it->reinitialized_ns;
  }
  return initialized_at_ns;
}

void UpdateLog::Add(const UpdateDiagnostics& u) {
  ++count_;
  unusable_ += u.usable ? 0 : 1;
  deferred_ += u.marginalization_deferred ? 1 : 0;
  marginalized_unusable_ += static_cast<std::uint64_t>(std::max(0, u.num_marginalized_unusable));
  left_out_of_prior_ += static_cast<std::uint64_t>(std::max(0, u.num_left_out_of_prior));
  iterations_ += u.iterations;
  const double ms = std::max(0.0, u.solve_time_s * 1e3);
  solve_ms_.Add(ms);
  for (const auto& [type, n] : u.factors) {
    if (n > 0) ++with_factor_[type];
  }
  recent_.push_back(u);
  if (recent_.size() > kRecent) recent_.pop_front();
  if (!first_ns_) first_ns_ = u.t_ns;
  // A stamp past the current period closes it; the next starts at the period holding the stamp
  // (periods without updates are not listed).
  const double since_s = ToSeconds(u.t_ns - *first_ns_);
  if (since_s >= period_start_s_ + kPeriodS) {
    closed_.push_back(CurrentPeriod());
    period_ms_ = RunningStatistics();
    period_start_s_ = std::floor(since_s / kPeriodS) * kPeriodS;
  }
  period_ms_.Add(ms);
}

double UpdateLog::mean_iterations() const {
  return count_ ? iterations_ / static_cast<double>(count_) : 0.0;
}

UpdateLog::Period UpdateLog::CurrentPeriod() const {
  Period p;
  p.start_s = ToSeconds(first_ns_.value_or(0)) + period_start_s_;
  p.count = period_ms_.count();
  p.median_ms = period_ms_.Median();
  p.p99_ms = period_ms_.Quantile(0.99);
  p.max_ms = period_ms_.max();
  return p;
}

std::vector<UpdateLog::Period> UpdateLog::Periods() const {
  std::vector<Period> out = closed_;
  if (first_ns_) out.push_back(CurrentPeriod());
  return out;
}

}  // namespace statebench::est
