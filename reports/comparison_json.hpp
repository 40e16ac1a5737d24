// A regression comparison (reports/paired_comparison.hpp) as JSON, the input of the compare
// report's plots (reports/python/statebench_reports/compare_report.py, docs/reports.md).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "reports/paired_comparison.hpp"

namespace statebench::reports {

// {"base": {"name", "runs"}, "candidate": {...}, "pairs", "significance", "unpaired": [...],
//  "metrics": [{"estimator", "metric", "better", "target" (null unless closer), "pairs",
//               "base_median", "candidate_median", "median_difference",
//               "difference_interval": [low, high], "p_value", "threshold", "verdict",
//               "paired": [{"key", "base", "candidate", "difference"}, ...]}, ...]}
// Non-finite figures are null.
nlohmann::json ComparisonJson(const Comparison& c, const std::string& base_name,
                              const std::string& candidate_name, double significance);

}  // namespace statebench::reports
