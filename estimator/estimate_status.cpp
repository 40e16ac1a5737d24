#include "estimator/estimate_status.hpp"

#include <algorithm>

namespace statebench::est {

EstimateStatus StatusAt(const EstimatorDiagnostics& diagnostics,
                        const std::vector<std::string>& position_sensors, TimeNs t_ns) {
  if (position_sensors.empty() || diagnostics.local_frame) return EstimateStatus::kLocal;
  if (!diagnostics.lost.empty()) {
    const auto reinitialized = diagnostics.lost.back().reinitialized_ns;
    if (reinitialized && t_ns - *reinitialized < FromSeconds(kRecoveringForS)) {
      return EstimateStatus::kRecovering;
    }
  }
  TimeNs last_ns = 0;
  for (const std::string& id : position_sensors) {
    const auto it = diagnostics.sensors.find(id);
    if (it != diagnostics.sensors.end()) last_ns = std::max(last_ns, it->second.last_accepted_ns);
  }
  if (last_ns == 0 || t_ns - last_ns > FromSeconds(kDeadReckoningAfterS)) {
    return EstimateStatus::kDeadReckoning;
  }
  return EstimateStatus::kGlobal;
}

}  // namespace statebench::est
