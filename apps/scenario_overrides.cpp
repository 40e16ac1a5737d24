#include "apps/scenario_overrides.hpp"

#include <stdexcept>

namespace statebench::app {

sim::Scenario LoadScenarioWithOverrides(const CliArgs& args) {
  sim::Scenario scenario = sim::LoadScenario(args.positional().at(0));
  if (const auto seed = args.Unsigned("seed")) scenario.seed = *seed;
  if (const auto duration = args.Double("duration")) {
    if (!(*duration > 0.0)) throw std::invalid_argument("--duration: must be positive");
    scenario.duration_s = *duration;
  }
  return scenario;
}

}  // namespace statebench::app
