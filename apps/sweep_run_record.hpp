// What the sweep stores of one finished run: status from the exit code and the run's files,
// every metric of each estimator's metrics.json, the files' paths, the stage cache's hits.
#pragma once

#include <filesystem>
#include <string>

#include "apps/process_pool.hpp"
#include "apps/sweep_expansion.hpp"
#include "reports/results_store.hpp"

namespace statebench::app {

// A run is ok when it exited 0 and wrote run.json and each estimator's metrics.json; otherwise
// it is failed with the last lines of its stderr (or the signal that killed it) as its error.
reports::RunRecord RecordOfFinishedRun(const SweepRun& run, const std::string& sweep,
                                       const std::string& code_version, const ChildExit& exit,
                                       const std::filesystem::path& dir);

}  // namespace statebench::app
