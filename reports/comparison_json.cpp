#include "reports/comparison_json.hpp"

#include <cmath>

namespace statebench::reports {
namespace {

nlohmann::json Number(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); }

}  // namespace

nlohmann::json ComparisonJson(const Comparison& c, const std::string& base_name,
                              const std::string& candidate_name, double significance) {
  nlohmann::json metrics = nlohmann::json::array();
  for (const MetricComparison& m : c.metrics) {
    nlohmann::json paired = nlohmann::json::array();
    for (const MetricComparison::Pair& p : m.paired) {
      paired.push_back({{"key", p.key},
                        {"base", Number(p.base)},
                        {"candidate", Number(p.candidate)},
                        {"difference", Number(p.difference)}});
    }
    metrics.push_back(
        {{"estimator", m.estimator},
         {"metric", m.metric},
         {"better", m.better},
         {"target", m.target ? Number(*m.target) : nlohmann::json()},
         {"pairs", m.pairs},
         {"base_median", Number(m.base_median)},
         {"candidate_median", Number(m.candidate_median)},
         {"median_difference", Number(m.median_difference)},
         {"difference_interval",
          {Number(m.difference_interval.low), Number(m.difference_interval.high)}},
         {"p_value", Number(m.p_value)},
         {"threshold", Number(m.threshold)},
         {"verdict", VerdictName(m.verdict)},
         {"paired", paired}});
  }
  return {{"base", {{"name", base_name}, {"runs", c.base_runs}}},
          {"candidate", {{"name", candidate_name}, {"runs", c.candidate_runs}}},
          {"pairs", c.pairs},
          {"significance", significance},
          {"unpaired", c.unpaired},
          {"metrics", metrics}};
}

}  // namespace statebench::reports
