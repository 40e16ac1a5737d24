// Scenario loading with the command-line overrides shared by simulate, record and run.
#pragma once

#include "apps/cli_args.hpp"
#include "simulator/scenario.hpp"

namespace statebench::app {

// LoadScenario(positional[0]) with --seed N and --duration S applied. Throws InputError on a bad
// scenario, std::invalid_argument on a bad option value.
sim::Scenario LoadScenarioWithOverrides(const CliArgs& args);

}  // namespace statebench::app
