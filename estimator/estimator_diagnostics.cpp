#include "estimator/estimator_diagnostics.hpp"

#include <algorithm>

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

}  // namespace statebench::est
