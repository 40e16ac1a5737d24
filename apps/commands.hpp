// The statebench subcommands. Each takes its arguments (after the subcommand name) and returns
// the process exit code: 0 success, 1 failure while running, 2 bad usage or bad input.
#pragma once

#include <string>
#include <vector>

namespace statebench::app {

int RunSimulate(const std::vector<std::string>& args);
int RunRecord(const std::vector<std::string>& args);
int RunEstimate(const std::vector<std::string>& args);
int RunRun(const std::vector<std::string>& args);
int RunOdometry(const std::vector<std::string>& args);
int RunSuite(const std::vector<std::string>& args);
int RunSweep(const std::vector<std::string>& args);
int RunResults(const std::vector<std::string>& args);
int RunCompare(const std::vector<std::string>& args);
int RunReportCommand(const std::vector<std::string>& args);
int RunImport(const std::vector<std::string>& args);  // import rosbag BAG ...
int RunExport(const std::vector<std::string>& args);  // export rosbag LOG ...

}  // namespace statebench::app
