#include "apps/cpu_profile.hpp"

#include <sys/resource.h>

#include "apps/process_pool.hpp"

namespace statebench::app {

double ChildProcessesCpuSeconds() {
  rusage usage{};
  return getrusage(RUSAGE_CHILDREN, &usage) == 0 ? CpuSeconds(usage) : 0.0;
}

CpuProfile::CpuProfile()
    : stages_start_(CurrentStageTimes()),
      process_cpu_start_s_(ProcessCpuSeconds()),
      children_cpu_start_s_(ChildProcessesCpuSeconds()) {}

nlohmann::json CpuProfile::Json(const std::vector<FedEstimator>& estimators,
                                double simulated_s) const {
  const StageTimes span = CurrentStageTimes() - stages_start_;
  const double process_s = ProcessCpuSeconds() - process_cpu_start_s_;
  const double children_s = ChildProcessesCpuSeconds() - children_cpu_start_s_;
  const CpuAttribution attribution(span, process_s);
  const auto split = attribution.Split(span);
  nlohmann::json stages = nlohmann::json::object();
  for (std::size_t i = 0; i < kStageCount; ++i) {
    stages[std::string(StageName(static_cast<Stage>(i)))] = split[i];
  }
  nlohmann::json per_estimator = nlohmann::json::object();
  for (const FedEstimator& f : estimators) per_estimator[f.label] = attribution.Total(f.time);
  const double total_s = process_s + children_s;
  return {{"process_s", process_s},
          {"child_processes_s", children_s},
          {"total_s", total_s},
          {"simulated_per_cpu_s", total_s > 0.0 ? simulated_s / total_s : 0.0},
          {"stages_s", stages},
          {"estimators_s", per_estimator}};
}

}  // namespace statebench::app
