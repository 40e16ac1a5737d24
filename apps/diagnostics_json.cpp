#include "apps/diagnostics_json.hpp"

#include <algorithm>

#include "core/running_statistics.hpp"

namespace statebench::app {
namespace {

constexpr int kSolveHistogramBinsPerDecade = 10;

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
    if (c.covariance_scale) sensors[id]["covariance_scale"] = *c.covariance_scale;
    for (const auto& [name, g] : c.globals) {
      nlohmann::json history = nlohmann::json::array();
      for (const est::GlobalDiagnostics::Sample& h : g.history) {
        history.push_back({ToSeconds(h.t_ns), h.value, h.sigma});
      }
      sensors[id]["globals"][name] = {{"value", g.value},
                                      {"sigma", g.sigma},
                                      {"clamped", g.clamped},
                                      {"history_t_value_sigma", history}};
    }
  }
  const est::UpdateLog& u = d.updates;
  nlohmann::json periods = nlohmann::json::array();
  for (const est::UpdateLog::Period& p : u.Periods()) {
    periods.push_back({{"start_s", p.start_s},
                       {"count", p.count},
                       {"solve_ms_median", p.median_ms},
                       {"solve_ms_p99", p.p99_ms},
                       {"solve_ms_max", p.max_ms}});
  }
  // Every update's solve time in 10 bins per decade (the run report's histogram).
  nlohmann::json histogram = {{"bins_per_decade", kSolveHistogramBinsPerDecade},
                              {"low_ms", nlohmann::json::array()},
                              {"high_ms", nlohmann::json::array()},
                              {"count", nlohmann::json::array()}};
  for (const RunningStatistics::LogBin& b : u.solve_ms().LogHistogram(kSolveHistogramBinsPerDecade)) {
    histogram["low_ms"].push_back(b.low);
    histogram["high_ms"].push_back(b.high);
    histogram["count"].push_back(b.count);
  }
  nlohmann::json lost = nlohmann::json::array();
  for (const est::LostEpisode& e : d.lost) {
    nlohmann::json j = {{"at_s", ToSeconds(e.at_ns)}, {"reason", e.reason}};
    if (e.reinitialized_ns) {
      j["reinitialized_at_s"] = ToSeconds(*e.reinitialized_ns);
      j["reinitialization"] = e.reinitialization;
    } else {
      j["reinitialization"] = "pending";
    }
    lost.push_back(j);
  }
  nlohmann::json enu_switches = nlohmann::json::array();
  for (const est::EnuSwitch& s : d.enu_switches) {
    enu_switches.push_back({{"at_s", ToSeconds(s.at_ns)},
                            {"fixes", s.fixes},
                            {"span_m", s.span_m},
                            {"yaw_rad", s.yaw_rad},
                            {"translation_m", s.translation_m},
                            {"yaw_sigma_rad", s.yaw_sigma_rad},
                            {"sigma_h_m", s.sigma_h_m},
                            {"residual_sigma_h_m", s.residual_sigma_h_m}});
  }
  nlohmann::json batch_solves = nlohmann::json::array();
  for (const est::BatchSolve& b : d.batch_solves) {
    batch_solves.push_back({{"begin_s", ToSeconds(b.begin_ns)},
                            {"end_s", ToSeconds(b.end_ns)},
                            {"states", b.states},
                            {"iterations", b.iterations},
                            {"initial_cost", b.initial_cost},
                            {"final_cost", b.final_cost},
                            {"usable", b.usable},
                            {"solve_s", b.solve_s}});
  }
  nlohmann::json imu_noise;  // null: the estimator does not measure it (the EKF)
  if (d.imu_noise) {
    const est::ImuNoiseReport& n = *d.imu_noise;
    imu_noise = {{"enabled", n.enabled},
                 {"blocks", n.blocks},
                 {"gyro_noise_density", {{"configured", n.gyro_configured},
                                         {"measured", n.gyro_measured},
                                         {"used", n.gyro_used},
                                         {"used_max", n.gyro_used_max}}},
                 {"accel_noise_density", {{"configured", n.accel_configured},
                                          {"measured", n.accel_measured},
                                          {"used", n.accel_used},
                                          {"used_max", n.accel_used_max}}}};
  }
  return {{"initialized", d.initialized},
          {"initialized_at_s", ToSeconds(d.initialized_at_ns)},
          {"initialization", d.initialization},
          {"waiting_for", d.waiting_for.empty() ? nlohmann::json() : nlohmann::json(d.waiting_for)},
          {"warnings", d.warnings},
          {"lost", lost},
          {"local_frame", d.local_frame},
          {"enu_switches", enu_switches},
          {"batch_solves", batch_solves},
          {"sensors", sensors},
          {"imu_noise", imu_noise},
          {"updates",
           {{"count", u.count()},
            {"unusable", u.unusable()},
            {"marginalization_deferred", u.deferred_marginalizations()},
            {"marginalized_unusable", u.marginalized_unusable()},
            {"left_out_of_prior", u.left_out_of_prior()},
            {"mean_iterations", u.mean_iterations()},
            {"solve_ms_mean", u.solve_ms().mean()},
            {"solve_ms_median", u.solve_ms().Median()},
            {"solve_ms_p95", u.solve_ms().Quantile(0.95)},
            {"solve_ms_p99", u.solve_ms().Quantile(0.99)},
            {"solve_ms_max", u.solve_ms().max()},
            {"with_factor", u.with_factor()},
            {"per_minute", periods},
            {"solve_ms_histogram", histogram}}}};
}


}  // namespace statebench::app
