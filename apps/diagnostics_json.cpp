#include "apps/diagnostics_json.hpp"

#include <algorithm>

namespace statebench::app {
namespace {

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5));
  return v[i];
}

}  // namespace

nlohmann::json DiagnosticsJson(const est::EstimatorDiagnostics& d) {
  nlohmann::json sensors = nlohmann::json::object();
  for (const auto& [id, c] : d.sensors) {
    nlohmann::json rejected = nlohmann::json::object();
    for (const auto& [reason, n] : c.rejected) {
      rejected[std::string(est::RejectReasonName(reason))] = n;
    }
    sensors[id] = {{"received", c.received},
                   {"accepted", c.accepted},
                   {"rejected", rejected},
                   {"downweighted", c.downweighted},
                   {"events", c.events},
                   {"last_accepted_s", ToSeconds(c.last_accepted_ns)}};
  }
  std::vector<double> times;
  double iterations = 0.0;
  std::size_t unusable = 0;
  for (const auto& u : d.updates) {
    times.push_back(u.solve_time_s * 1e3);
    iterations += u.iterations;
    unusable += u.usable ? 0 : 1;
  }
  double mean = 0.0;
  for (const double t : times) mean += t;
  if (!times.empty()) mean /= static_cast<double>(times.size());
  nlohmann::json lost = nlohmann::json::array();
  for (std::size_t k = 0; k < d.lost_at_ns.size(); ++k) {
    lost.push_back({{"at_s", ToSeconds(d.lost_at_ns[k])},
                    {"reinitialization",
                     k < d.reinitializations.size() ? d.reinitializations[k] : "pending"}});
  }
  return {{"initialized", d.initialized},
          {"initialized_at_s", ToSeconds(d.initialized_at_ns)},
          {"initialization", d.initialization},
          {"lost", lost},
          {"sensors", sensors},
          {"updates",
           {{"count", d.updates.size()},
            {"unusable", unusable},
            {"mean_iterations", d.updates.empty() ? 0.0 : iterations / d.updates.size()},
            {"solve_ms_mean", mean},
            {"solve_ms_median", Percentile(times, 0.5)},
            {"solve_ms_p95", Percentile(times, 0.95)},
            {"solve_ms_p99", Percentile(times, 0.99)},
            {"solve_ms_max", times.empty() ? 0.0 : *std::max_element(times.begin(), times.end())}}}};
}


}  // namespace statebench::app
