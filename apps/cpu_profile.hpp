// Where the CPU time of a run or an estimate went, for run.json / profile.json "cpu"
// (docs/cli.md): the process's CPU time split by stage (core/stage_profile.hpp), each
// estimator's share, and the CPU time of child processes (SUMO, netconvert).
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "apps/estimator_feed.hpp"
#include "core/stage_profile.hpp"

namespace statebench::app {

class CpuProfile {
 public:
  // The span starts now.
  CpuProfile();

  // {"process_s", "child_processes_s", "total_s", "simulated_per_cpu_s", "stages_s": {stage: s},
  //  "estimators_s": {label: s}} over the span up to now; simulated_s: the span's simulated (or
  //  logged) time.
  nlohmann::json Json(const std::vector<FedEstimator>& estimators, double simulated_s) const;

 private:
  StageTimes stages_start_;
  double process_cpu_start_s_ = 0.0;
  double children_cpu_start_s_ = 0.0;
};

// CPU seconds (user + system) of the waited-for child processes so far.
double ChildProcessesCpuSeconds();

}  // namespace statebench::app
