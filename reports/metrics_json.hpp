// JSON form of the metrics (the metrics files written next to every estimate).
#pragma once

#include <nlohmann/json.hpp>

#include "reports/trajectory_metrics.hpp"

namespace statebench::reports {

nlohmann::json ToJson(const ErrorStatistics& s);
nlohmann::json ToJson(const StepStatistics& s);
nlohmann::json ToJson(const OutputSteps& s);  // {position_m, yaw_rad}: p50, p99, max, count
nlohmann::json ToJson(const TrajectoryMetrics& m);

}  // namespace statebench::reports
